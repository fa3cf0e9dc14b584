; The package waits at the depot; it must reach the office.
;
;   depot --- hall ==door== office
;     |        |              |
;   corridor --+---------- annex
(define (problem deliver-to-office)
  (:domain delivery)
  (:objects depot hall office corridor annex - room parcel - package)
  (:init
    (at depot)
    (package-at parcel depot)
    (connected depot hall) (connected hall depot)
    (connected hall office) (connected office hall)
    (connected depot corridor) (connected corridor depot)
    (connected hall corridor) (connected corridor hall)
    (connected corridor annex) (connected annex corridor)
    (connected annex office) (connected office annex))
  (:goal (package-at parcel office)))
