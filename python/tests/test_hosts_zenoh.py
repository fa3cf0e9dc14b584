"""A run across hosts, watched from Python: the `eclipse-zenoh` package as an
independent Zenoh client of the run's link reads the heartbeats the bridges
carry (raw `Heartbeat` layouts tagged with their type and protocol
version), decoded with the world kit's ctypes mirror. Host A (the corridor
world, its supervisor and bridge) and host B (`learnpnp-supervisor remote`,
the agent) run on loopback endpoints here; the Rust tests run the hosts in
two network namespaces.
"""

import json
import os
import socket
import subprocess
import time

import pytest

zenoh = pytest.importorskip("zenoh")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_zenoh_peer_reads_the_heartbeats_of_a_run_across_hosts(supervisor, sandbox, plans):
    from learnpnp.world import Heartbeat

    endpoint = f"tcp/127.0.0.1:{free_port()}"
    corridor = os.path.join(os.path.dirname(supervisor), "learnpnp-corridor")
    host_a = subprocess.Popen(
        [supervisor, "--world-cmd", corridor, "--plan", str(plans / "corridor.pnml"), "--algo", "q-learning",
         "--episodes", "1500", "--eval-every", "1500", "--eval-episodes", "0", "--greedy-episodes", "2",
         "--remote-agents", "1", "--bridge-listen", endpoint, "--out", str(sandbox / "a"), "--floor-round-trips",
         "500"],
        env={**os.environ, "LEARNPNP_IPC_DIR": str(sandbox / "ipc-a")}, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True)
    host_b = subprocess.Popen(
        [supervisor, "remote", "--bridge-connect", endpoint, "--out", str(sandbox / "b")],
        env={**os.environ, "LEARNPNP_IPC_DIR": str(sandbox / "ipc-b")}, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True)
    config = zenoh.Config()
    config.insert_json5("mode", '"client"')
    config.insert_json5("connect/endpoints", json.dumps([endpoint]))
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("connect/timeout_ms", "30000")  # host A's bridge may not listen yet
    heard = {}
    try:
        with zenoh.open(config) as session:
            subscriber = session.declare_subscriber("learnpnp/*/learnpnp/heartbeat")
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline and len(heard) < 2:
                sample = subscriber.try_recv()
                if sample is None:
                    time.sleep(0.01)
                    continue
                assert bytes(sample.attachment) == b"learnpnp::Heartbeat;1"
                beat = Heartbeat.from_buffer_copy(bytes(sample.payload))
                heard[beat.header.sender] = beat
    finally:
        a_out, a_err = host_a.communicate(timeout=120)
        b_out, b_err = host_b.communicate(timeout=120)
    assert host_a.returncode == 0, a_err
    assert host_b.returncode == 0, b_err
    run_id = json.loads((sandbox / "b" / "summary.json").read_text())["run_id"]
    assert set(heard) == {0, 100}, "the agent's (host B) and the world's (host A) heartbeats"
    assert all(beat.header.run_id == run_id and beat.pid > 0 for beat in heard.values())
    summary = json.loads((sandbox / "a" / "summary.json").read_text())
    assert summary["complete"] and summary["experiment"]["final_greedy_mean"] == -4.0
