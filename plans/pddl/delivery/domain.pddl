; A robot delivers a package between rooms. The model a planner sees: every
; connection can be taken at unit cost. The world (python/examples/
; delivery_world.py) differs: the door between hall and office is often
; locked, moves into and out of the corridor slip, and the corridor is long.
(define (domain delivery)
  (:requirements :strips :typing)
  (:types room package)
  (:predicates
    (at ?r - room)
    (connected ?from ?to - room)
    (package-at ?p - package ?r - room)
    (holding ?p - package))
  (:action move
    :parameters (?from ?to - room)
    :precondition (and (at ?from) (connected ?from ?to))
    :effect (and (at ?to) (not (at ?from))))
  (:action pick
    :parameters (?p - package ?r - room)
    :precondition (and (at ?r) (package-at ?p ?r))
    :effect (and (holding ?p) (not (package-at ?p ?r))))
  (:action drop
    :parameters (?p - package ?r - room)
    :precondition (and (at ?r) (holding ?p))
    :effect (and (package-at ?p ?r) (not (holding ?p)))))
