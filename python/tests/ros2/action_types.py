"""ROS 2 interface types and their RIHS01 hashes as the ``rosbags`` package
computes them (``Typestore.hash_rihs01``), an implementation of REP-2016's
type hash no one here wrote: learnpnp's Rust code must agree with it.

rosbags hashes messages only. A service and an action's synthesized types are
built here as rosidl builds them (rosidl_adapter and rosidl_parser's action
synthesis; rosidl_generator_type_description for the service's description):

- a service ``S`` is a type with the fields ``request_message`` (``S_Request``),
  ``response_message`` (``S_Response``) and ``event_message`` (``S_Event``:
  ``service_msgs/ServiceEventInfo info``, ``S_Request[<=1] request``,
  ``S_Response[<=1] response``);
- an action ``A`` brings ``A_Goal``, ``A_Result``, ``A_Feedback``, the services
  ``A_SendGoal`` (request ``unique_identifier_msgs/UUID goal_id``, ``A_Goal
  goal``; response ``bool accepted``, ``builtin_interfaces/Time stamp``) and
  ``A_GetResult`` (request ``goal_id``; response ``int8 status``, ``A_Result
  result``) and the message ``A_FeedbackMessage`` (``goal_id``, ``A_Feedback
  feedback``);
- a ``.msg`` ``char`` is IDL ``uint8`` (rosidl_adapter), so ServiceEventInfo's
  ``client_gid`` is written ``uint8[16]`` here.

Run as a script, it prints the hashes of an action file's types:
``python action_types.py example_interfaces/action/Fibonacci Fibonacci.action``.
"""

import sys

from rosbags.typesys import Stores, get_types_from_msg, get_typestore

# Facts from ROS 2's rcl_interfaces (service_msgs), unique_identifier_msgs and
# builtin_interfaces (Jazzy); char written as the uint8 rosidl makes it.
BASE = {
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec",
    "unique_identifier_msgs/msg/UUID": "uint8[16] uuid",
    "service_msgs/msg/ServiceEventInfo": (
        "uint8 event_type\nbuiltin_interfaces/msg/Time stamp\nuint8[16] client_gid\nint64 sequence_number"
    ),
}


def _fix(name):
    """rosbags files ``pkg/srv/X`` under ``pkg/srv/msg/X``: undo it."""
    return name.replace("/srv/msg/", "/srv/")


def _fix_desc(desc):
    kind, rest = desc
    if isinstance(rest, str):
        return (kind, _fix(rest))
    if isinstance(rest, tuple) and len(rest) == 2 and isinstance(rest[0], tuple):
        return (kind, (_fix_desc(rest[0]), rest[1]))
    return desc


class Types:
    """A rosbags type store of messages, services and actions by their ROS 2 names."""

    def __init__(self):
        self.store = get_typestore(Stores.EMPTY)
        for name, text in BASE.items():
            self.msg(name, text)

    def msg(self, name, text):
        """Adds a message (``.msg`` text) under its full name."""
        parsed = get_types_from_msg(text, "tmp/msg/T")
        consts, fields = parsed["tmp/msg/T"]
        fields = [(f, _fix_desc(d)) for f, d in fields]
        self.store.register({name: (consts, fields)})

    def srv(self, name, request, response):
        """Adds a service from its request and response text, as rosidl describes it."""
        self.msg(f"{name}_Request", request)
        self.msg(f"{name}_Response", response)
        self.msg(
            f"{name}_Event",
            f"service_msgs/msg/ServiceEventInfo info\n{name}_Request[<=1] request\n{name}_Response[<=1] response",
        )
        self.msg(
            name,
            f"{name}_Request request_message\n{name}_Response response_message\n{name}_Event event_message",
        )

    def action(self, name, text):
        """Adds an action (``.action`` text: goal ``---`` result ``---`` feedback) and its synthesized types."""
        goal, result, feedback = (part.strip() for part in text.split("\n---"))
        self.msg(f"{name}_Goal", goal)
        self.msg(f"{name}_Result", result)
        self.msg(f"{name}_Feedback", feedback)
        uuid = "unique_identifier_msgs/msg/UUID goal_id"
        self.srv(
            f"{name}_SendGoal",
            f"{uuid}\n{name}_Goal goal",
            "bool accepted\nbuiltin_interfaces/msg/Time stamp",
        )
        self.srv(f"{name}_GetResult", uuid, f"int8 status\n{name}_Result result")
        self.msg(f"{name}_FeedbackMessage", f"{uuid}\n{name}_Feedback feedback")

    def hash(self, name):
        """The type's RIHS01 hash, by rosbags."""
        return self.store.hash_rihs01(name)


def action_hashes(name, text):
    """The RIHS01 hashes of an action's ``_SendGoal``, ``_GetResult`` and ``_FeedbackMessage``."""
    types = Types()
    types.action(name, text)
    return {suffix: types.hash(f"{name}{suffix}") for suffix in ("_SendGoal", "_GetResult", "_FeedbackMessage")}


if __name__ == "__main__":
    action, path = sys.argv[1], sys.argv[2]
    with open(path) as f:
        for suffix, digest in action_hashes(action, f.read()).items():
            print(f"{action}{suffix} {digest}")
