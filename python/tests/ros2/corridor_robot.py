"""A corridor robot as a ROS 2 node over rmw_zenoh's wire format, written with
zenoh-ros2-sdk (ROBOTIS's independent implementation of that format): no
learnpnp code here.

The robot stands in a corridor of five cells, starting in the first. It takes
``std_msgs/Int32`` commands on ``/corridor/cmd`` (+1 forward, -1 back), and
after each one publishes ``-1`` on ``/corridor/reward`` (``std_msgs/Float64``),
its state (``/corridor/at_end`` ``std_msgs/Bool``, ``/corridor/position``
``std_msgs/Int32``, ``/corridor/range`` ``sensor_msgs/Range``: the distance to
the far wall) and last a tick on ``/corridor/tick`` (``std_msgs/Int32``), the
lock-step answer. ``/corridor/reset`` (``corridor_msgs/srv/Reset``) puts it
back at ``start``.

With ``--action``, the commands are goals of the ROS 2 action
``/corridor/move`` (``corridor_msgs/action/Move``: direction, then position as
feedback and result) instead of ``/corridor/cmd`` messages. zenoh-ros2-sdk has
no action server, so the robot makes one of what ROS 2 makes an action of:
the services ``_action/send_goal``, ``_action/get_result`` and
``_action/cancel_goal`` and the topics ``_action/feedback`` and
``_action/status``, with the synthesized types' hashes computed by the
``rosbags`` package (``action_types.py``). A goal is accepted, then executed
(status executing, feedback, the move, the state, status succeeded); its
result is answered once it is done. With ``--stall N``, the N-th goal is
accepted but not executed until it is canceled (``_action/cancel_goal``:
status canceled); the robot prints ``canceled K`` for the K-th goal it cancels.

With ``--log FILE``, the robot appends the wall-clock time (ns) of each
command, one a line.

With ``--plan-state FILE``, the robot also subscribes, as ``ros2 topic echo``
would, to the agent's plan state (``std_msgs/String`` on
``/learnpnp/agent1/pnp/currentActivePlaces``, ``.../runningActions`` and
``.../choices``) and appends each message to FILE as a line of JSON
(``{"topic": ..., "data": ...}``), its own commands (``{"topic": "command",
"data": "forward"}`` or ``"back"``) and resets (``{"topic": "reset"}``)
among them: one timeline of what it was told and what it was shown.

With ``--faults N``, after its N-th command the robot also sends, once, a
``Bool`` whose CDR byte is 7 (malformed) and a ``Bool`` under a wrong type
hash, before its true state; with ``--action``, the N-th goal's status list
also carries, once, the status 9, which action_msgs does not define.

Message definitions come from ``msgs/`` beside this file: nothing is fetched.
"""

import argparse
import json
import os
import pathlib
import signal
import sys
import threading
import time

LENGTH = 5
MSGS = pathlib.Path(__file__).resolve().parent / "msgs"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, required=True, help="the router's port on 127.0.0.1")
    parser.add_argument("--faults", type=int, default=0, help="send bad messages after this command (0: never)")
    parser.add_argument("--action", action="store_true", help="take commands as goals of the /corridor/move action")
    parser.add_argument("--log", help="append each command's time (ns) to this file")
    parser.add_argument("--stall", type=int, default=0, help="with --action: hold this goal until canceled (0: none)")
    parser.add_argument("--plan-state", help="append the agent's plan-state messages to this file")
    args = parser.parse_args()
    # Contact nothing but the router on 127.0.0.1: no multicast, no gossip, no listener.
    os.environ["ZENOH_CONFIG_OVERRIDE"] = (
        "scouting/multicast/enabled=false;scouting/gossip/enabled=false;listen/endpoints=[]"
    )
    os.environ["ZENOH_ROS2_SDK_CACHE"] = str(pathlib.Path(os.environ.get("TMPDIR", "/tmp")) / "no-sdk-cache")
    import zenoh
    from zenoh_ros2_sdk import ROS2Publisher, ROS2ServiceServer, ROS2Subscriber, get_registry
    from zenoh_ros2_sdk.attachment import Attachment

    get_registry(str(MSGS))
    where = dict(router_ip="127.0.0.1", router_port=args.port, node_name="corridor_robot")

    def publisher(topic, msg_type):
        return ROS2Publisher(topic, msg_type, **where)

    at_end = publisher("/corridor/at_end", "std_msgs/msg/Bool")
    position = publisher("/corridor/position", "std_msgs/msg/Int32")
    ranger = publisher("/corridor/range", "sensor_msgs/msg/Range")
    reward = publisher("/corridor/reward", "std_msgs/msg/Float64")
    tick = publisher("/corridor/tick", "std_msgs/msg/Int32")
    store = at_end.session_mgr.store
    header_cls = store.types["std_msgs/msg/Header"]
    time_cls = store.types["builtin_interfaces/msg/Time"]
    lock = threading.Lock()
    state = {"pos": 0, "ticks": 0, "commands": 0}

    def publish_state():
        pos = state["pos"]
        at_end.publish(data=pos == LENGTH - 1)
        position.publish(data=pos)
        now = time.time_ns()
        stamp = time_cls(sec=now // 10**9, nanosec=now % 10**9)
        ranger.publish(
            header=header_cls(stamp=stamp, frame_id="corridor"),
            radiation_type=1,
            field_of_view=0.1,
            min_range=0.0,
            max_range=float(LENGTH),
            range=float(LENGTH - 1 - pos),
        )
        state["ticks"] += 1
        tick.publish(data=state["ticks"])

    def send_faults():
        session = at_end.session_mgr.session
        gid = bytes(16)
        attachment = zenoh.ZBytes(Attachment(sequence_id=1, timestamp_ns=time.time_ns(), gid=gid).to_bytes())
        session.put(at_end.keyexpr, zenoh.ZBytes(b"\x00\x01\x00\x00\x07"), attachment=attachment)
        wrong = at_end.keyexpr.rsplit("/", 1)[0] + "/RIHS01_" + "0" * 64
        session.put(wrong, zenoh.ZBytes(b"\x00\x01\x00\x00\x01"), attachment=attachment)

    log = open(args.log, "a", buffering=1) if args.log else None
    echo = open(args.plan_state, "a", buffering=1) if args.plan_state else None
    echo_lock = threading.Lock()

    def record(message):
        """Appends ``message`` to the plan-state timeline, if one is kept."""
        if echo:
            with echo_lock:
                echo.write(json.dumps(message) + "\n")

    def move(direction):
        with lock:
            if log:
                log.write(f"{time.time_ns()}\n")
            record({"topic": "command", "data": "forward" if direction > 0 else "back"})
            state["commands"] += 1
            state["pos"] = min(max(state["pos"] + direction, 0), LENGTH - 1)
            reward.publish(data=-1.0)
            if state["commands"] == args.faults:
                send_faults()
            publish_state()
            return state["pos"]

    def on_reset(request):
        with lock:
            record({"topic": "reset"})
            state["pos"] = min(max(int(request.start), 0), LENGTH - 1)
            publish_state()
        return server.response_msg_class(success=True)

    if args.action:
        servers = serve_action(move, where, time_cls, args.faults, args.stall)  # kept for the robot's life
    else:
        ROS2Subscriber("/corridor/cmd", "std_msgs/msg/Int32", lambda msg: move(int(msg.data)), **where)
    server = ROS2ServiceServer("/corridor/reset", "corridor_msgs/srv/Reset", callback=on_reset, **where)
    if echo:

        def echoed(topic):
            return lambda msg: record({"topic": topic, "data": msg.data})

        for topic in ("currentActivePlaces", "runningActions", "choices"):
            name = f"/learnpnp/agent1/pnp/{topic}"
            ROS2Subscriber(name, "std_msgs/msg/String", echoed(topic), **where)
    print("ready", flush=True)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    while not stop.wait(0.2):
        pass
    # Zenoh's threads would keep the interpreter alive: leave at once.
    sys.stdout.flush()
    os._exit(0)


def serve_action(move, where, time_cls, faults, stall):
    """The robot's side of the ROS 2 action ``/corridor/move``, made of the
    SDK's service servers and publishers by ROS 2's action naming."""
    from action_types import Types
    from zenoh_ros2_sdk import ROS2Publisher, ROS2ServiceServer

    name, action = "/corridor/move", "corridor_msgs/action/Move"
    text = (MSGS / "corridor_msgs" / "action" / "Move.action").read_text()
    types = Types()
    types.action(action, text)
    goal_def, result_def, feedback_def = (part.strip() for part in text.split("\n---"))
    uuid = "unique_identifier_msgs/msg/UUID goal_id"
    definitions = {
        f"{action}_Goal": goal_def,
        f"{action}_Result": result_def,
        f"{action}_Feedback": feedback_def,
        f"{action}_FeedbackMessage": f"{uuid}\n{action}_Feedback feedback",
    }
    status_pub = ROS2Publisher(f"{name}/_action/status", "action_msgs/msg/GoalStatusArray", **where)
    session = status_pub.session_mgr
    session.register_message_type(None, "unique_identifier_msgs/msg/UUID")
    for type_name, definition in definitions.items():
        session.register_message_type(definition, type_name)
    feedback_pub = ROS2Publisher(
        f"{name}/_action/feedback",
        f"{action}_FeedbackMessage",
        msg_definition=definitions[f"{action}_FeedbackMessage"],
        type_hash=types.hash(f"{action}_FeedbackMessage"),
        **where,
    )
    store = session.store.types
    goal_info, goal_status = store["action_msgs/msg/GoalInfo"], store["action_msgs/msg/GoalStatus"]
    results = {}  # goal id -> (done event, [final status, position])
    goals = {"received": 0, "done": 0}
    lock = threading.Lock()

    def now():
        t = time.time_ns()
        return time_cls(sec=t // 10**9, nanosec=t % 10**9)

    def publish_status(goal_id, status):
        info = goal_info(goal_id=goal_id, stamp=now())
        status_pub.publish(status_list=[goal_status(goal_info=info, status=status)])

    def execute(goal_id, direction, done, out):
        publish_status(goal_id, 2)  # executing
        feedback = store[f"{action}_Feedback"]
        feedback_pub.publish(goal_id=goal_id, feedback=feedback(position=-1))
        position = move(direction)
        goals["done"] += 1
        if goals["done"] == faults:
            publish_status(goal_id, 9)  # not an action_msgs status
        publish_status(goal_id, 4)  # succeeded
        out.extend([4, position])
        done.set()

    def on_send_goal(request):
        done, out = threading.Event(), []
        with lock:
            results[bytes(request.goal_id.uuid)] = (done, out)
            goals["received"] += 1
            held = goals["received"] == stall
        if not held:
            threading.Thread(target=execute, args=(request.goal_id, int(request.goal.direction), done, out)).start()
        return send_goal.response_msg_class(accepted=True, stamp=now())

    def answer_results():
        """get_result's requests, each answered once its goal is done (the
        SDK's queue mode: a callback must not wait)."""
        result = store[f"{action}_Result"]

        def answer(key, done, out):
            if done is None or not done.wait(10.0):
                response = get_result.response_msg_class(status=6, result=result(position=-1))  # aborted
            else:
                response = get_result.response_msg_class(status=out[0], result=result(position=out[1]))
            try:
                get_result.send_response(key, response)
            except KeyError:
                pass  # the client is gone

        while True:
            key, request = get_result.take_request()
            with lock:
                done, out = results.get(bytes(request.goal_id.uuid), (None, None))
            threading.Thread(target=answer, args=(key, done, out), daemon=True).start()

    canceled = [0]

    def on_cancel(request):
        goal_id = request.goal_info.goal_id
        with lock:
            done, out = results.get(bytes(goal_id.uuid), (None, None))
        if done is None or done.is_set():
            return cancel.response_msg_class(return_code=3 if done else 2, goals_canceling=[])  # terminated, unknown
        publish_status(goal_id, 5)  # canceled
        out.extend([5, -1])
        done.set()
        canceled[0] += 1
        print(f"canceled {canceled[0]}", flush=True)
        info = goal_info(goal_id=goal_id, stamp=now())
        return cancel.response_msg_class(return_code=0, goals_canceling=[info])

    def service(suffix, key, callback, request, response):
        srv = f"{action}_{suffix}"
        return ROS2ServiceServer(
            f"{name}/_action/{key}",
            srv,
            callback=callback,
            mode="callback" if callback else "queue",
            request_definition=request,
            response_definition=response,
            type_hash=types.hash(srv),
            **where,
        )

    send_goal = service(
        "SendGoal", "send_goal", on_send_goal, f"{uuid}\n{action}_Goal goal", "bool accepted\nbuiltin_interfaces/msg/Time stamp"
    )
    get_result = service("GetResult", "get_result", None, uuid, f"int8 status\n{action}_Result result")
    threading.Thread(target=answer_results, daemon=True).start()
    # Its definitions given, so that the SDK does not look for them online,
    # with GoalInfo's full name (rosbags would look for it under srv/).
    cancel_text = (MSGS / "action_msgs" / "srv" / "CancelGoal.srv").read_text()
    cancel_request, cancel_response = cancel_text.replace("GoalInfo", "action_msgs/msg/GoalInfo").split("---")
    cancel = ROS2ServiceServer(
        f"{name}/_action/cancel_goal",
        "action_msgs/srv/CancelGoal",
        callback=on_cancel,
        request_definition=cancel_request.strip(),
        response_definition=cancel_response.strip(),
        **where,
    )
    return send_goal, get_result, cancel, feedback_pub, status_pub


if __name__ == "__main__":
    main()
