"""RIHS01 type hashes of ROS 2 actions' synthesized types, computed by an
independent implementation (the ``rosbags`` package, ``ros2/action_types.py``)
and compared with the golden values learnpnp's Rust code is tested against
(``crates/ros2/src/types.rs``, ``action_hashes_agree_with_rosbags``).

The types are built as rosidl builds them; the construction is checked first
on rmw_zenoh's design.md golden hashes (``std_msgs/msg/String``, and the
service ``example_interfaces/srv/AddTwoInts``, whose event message is built
the same way as an action's services').
"""

import pathlib
import sys

import pytest

pytest.importorskip("rosbags")
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "ros2"))

from action_types import Types, action_hashes  # noqa: E402

# rmw_zenoh docs/design.md, "Topic and Service name mapping to Zenoh key expressions".
DESIGN = {
    "std_msgs/msg/String": "df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
    "example_interfaces/srv/AddTwoInts": "e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a",
}

# The golden values of crates/ros2/src/types.rs (action_hashes_agree_with_rosbags).
FIBONACCI = {
    "_SendGoal": "d1a57fb2a4afe8c21e34fb10db206f16ce6729b28531141472df92277c55b557",
    "_GetResult": "1b0de0d5d29dc955d92f546706568428632771db13ec84c15ec1c1a59f424a57",
    "_FeedbackMessage": "c1de71afd52e49a89c53d8262366884185bc0a02f78ce051c4e46b0a7fe59bb2",
}


def test_the_rosidl_construction_gives_design_md_golden_hashes():
    types = Types()
    types.msg("std_msgs/msg/String", "string data")
    types.srv("example_interfaces/srv/AddTwoInts", "int64 a\nint64 b", "int64 sum")
    for name, digest in DESIGN.items():
        assert types.hash(name) == f"RIHS01_{digest}", name


def test_fibonacci_action_hashes_by_rosbags_are_the_rust_golden_values():
    text = "int32 order\n---\nint32[] sequence\n---\nint32[] sequence\n"
    got = action_hashes("example_interfaces/action/Fibonacci", text)
    assert got == {k: f"RIHS01_{v}" for k, v in FIBONACCI.items()}
