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

With ``--faults N``, after its N-th command the robot also sends, once, a
``Bool`` whose CDR byte is 7 (malformed) and a ``Bool`` under a wrong type
hash, before its true state.

Message definitions come from ``msgs/`` beside this file: nothing is fetched.
"""

import argparse
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

    def on_command(msg):
        with lock:
            state["commands"] += 1
            state["pos"] = min(max(state["pos"] + int(msg.data), 0), LENGTH - 1)
            reward.publish(data=-1.0)
            if state["commands"] == args.faults:
                send_faults()
            publish_state()

    def on_reset(request):
        with lock:
            state["pos"] = min(max(int(request.start), 0), LENGTH - 1)
            publish_state()
        return server.response_msg_class(success=True)

    ROS2Subscriber("/corridor/cmd", "std_msgs/msg/Int32", on_command, **where)
    server = ROS2ServiceServer("/corridor/reset", "corridor_msgs/srv/Reset", callback=on_reset, **where)
    print("ready", flush=True)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    while not stop.wait(0.2):
        pass
    # Zenoh's threads would keep the interpreter alive: leave at once.
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
