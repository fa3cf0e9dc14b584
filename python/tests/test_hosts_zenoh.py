"""A run across hosts, watched from Python: the `eclipse-zenoh` package as an
independent Zenoh client of the run's link, on host B, with the read-only
monitor certificate that `learnpnp-supervisor link-certs` made for the run
(QUIC with TLS 1.3, mutual authentication by the run's CA): it reads the
heartbeats the bridges carry (raw `Heartbeat` layouts tagged with their type,
protocol version and the sender's sequence number), decoded with the world kit's ctypes mirror, and cannot
publish (host A's access control denies it and counts it). Host A (the
corridor world, its supervisor and bridge) and host B (`learnpnp-supervisor
remote` with the agent, and the Zenoh client) are two network namespaces this
test creates, joined by a veth pair with addresses from 198.18.0.0/15 and
nothing else (removed after the test, also when it fails); where namespaces
cannot be made (not root), the test says so and runs both hosts on loopback
endpoints.
"""

import contextlib
import json
import os
import re
import socket
import subprocess
import sys
import time

import pytest

pytest.importorskip("zenoh")
PROTOCOL_VERSION = pytest.importorskip("learnpnp.world").PROTOCOL_VERSION

# Run by host B's Python (in host B's namespace), with the monitor's
# certificate: reads heartbeats from the link at ENDPOINT until it has heard
# two senders, then tries to publish a heartbeat and a stop order in the
# run's keys; prints what it heard as JSON.
CLIENT = r"""
import json, pathlib, sys, time
import zenoh
from learnpnp.world import Heartbeat
endpoint, certs = sys.argv[1], pathlib.Path(sys.argv[2])
config = zenoh.Config()
config.insert_json5("mode", '"client"')
config.insert_json5("connect/endpoints", json.dumps([endpoint]))
config.insert_json5("scouting/multicast/enabled", "false")
config.insert_json5("connect/timeout_ms", "30000")  # host A's bridge may not listen yet
tls = "transport/link/tls"
config.insert_json5(f"{tls}/root_ca_certificate", json.dumps(str(certs / "ca.pem")))
config.insert_json5(f"{tls}/enable_mtls", "true")
config.insert_json5(f"{tls}/connect_certificate", json.dumps(str(certs / "cert.pem")))
config.insert_json5(f"{tls}/connect_private_key", json.dumps(str(certs / "key.pem")))
config.insert_json5(f"{tls}/verify_name_on_connect", "true")
heard = {}
with zenoh.open(config) as session:
    # A monitor does not know the run's prefix: the wildcard is what it may ask for.
    subscriber = session.declare_subscriber("learnpnp/*/learnpnp/heartbeat/*")
    deadline = time.monotonic() + 60
    prefix = None
    while time.monotonic() < deadline and len(heard) < 2:
        sample = subscriber.try_recv()
        if sample is None:
            time.sleep(0.01)
            continue
        prefix = str(sample.key_expr).split("/")[1]
        tag = bytes(sample.attachment).decode()
        beat = Heartbeat.from_buffer_copy(bytes(sample.payload))
        heard[beat.header.sender] = {"tag": tag, "run_id": beat.header.run_id, "pid": beat.pid}
    # Read-only: these are denied by host A's access control.
    for key in (f"learnpnp/{prefix}/learnpnp/heartbeat/0", f"learnpnp/{prefix}/learnpnp/control/host-a"):
        session.put(key, b"monitor")
    time.sleep(0.5)
print(json.dumps(heard))
"""


def ip(*args):
    return subprocess.run(["ip", *args], capture_output=True).returncode == 0


@contextlib.contextmanager
def two_hosts():
    """Yields (wrap_a, wrap_b, host A's address): functions that make a
    command run on host A or host B, in namespaces if they can be made."""
    tag = f"{os.getpid() % 100000}"
    na, nb, la, lb = f"lpza{tag}", f"lpzb{tag}", f"lvza{tag}", f"lvzb{tag}"
    subnet = 1 + os.getpid() % 250
    a, b = f"198.18.{subnet}.1", f"198.18.{subnet}.2"
    made = (ip("netns", "add", na) and ip("netns", "add", nb)
            and ip("link", "add", la, "type", "veth", "peer", "name", lb)
            and ip("link", "set", la, "netns", na) and ip("link", "set", lb, "netns", nb)
            and ip("-n", na, "addr", "add", f"{a}/30", "dev", la)
            and ip("-n", nb, "addr", "add", f"{b}/30", "dev", lb)
            and ip("-n", na, "link", "set", la, "up") and ip("-n", nb, "link", "set", lb, "up")
            and ip("-n", na, "link", "set", "lo", "up") and ip("-n", nb, "link", "set", "lo", "up"))
    try:
        if made:
            yield (lambda cmd: ["ip", "netns", "exec", na, *cmd]), (lambda cmd: ["ip", "netns", "exec", nb, *cmd]), a
        else:
            print("note: network namespaces cannot be made here (not root?): both hosts run on loopback endpoints")
            yield (lambda cmd: cmd), (lambda cmd: cmd), "127.0.0.1"
    finally:
        # Deleting a namespace deletes the veth end in it, and its pair.
        ip("netns", "del", na)
        ip("netns", "del", nb)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_monitor_on_host_b_reads_the_heartbeats_of_a_run_across_hosts_and_cannot_publish(supervisor, sandbox, plans):
    corridor = os.path.join(os.path.dirname(supervisor), "learnpnp-corridor")
    with two_hosts() as (on_a, on_b, address):
        endpoint = f"quic/{address}:{free_port()}"
        certs = sandbox / "certs"
        subprocess.run([supervisor, "link-certs", "--dir", str(certs), "--host-a", address], check=True,
                       capture_output=True)
        host_a = subprocess.Popen(
            on_a([supervisor, "--world-cmd", corridor, "--plan", str(plans / "corridor.pnml"), "--algo",
                  "q-learning", "--episodes", "1500", "--eval-every", "1500", "--eval-episodes", "0",
                  "--greedy-episodes", "2", "--remote-agents", "1", "--bridge-listen", endpoint,
                  "--link-certs", str(certs / "host-a"), "--out", str(sandbox / "a"),
                  "--floor-round-trips", "500"]),
            env={**os.environ, "LEARNPNP_IPC_DIR": str(sandbox / "ipc-a")}, stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True)
        host_b = subprocess.Popen(
            on_b([supervisor, "remote", "--bridge-connect", endpoint, "--link-certs", str(certs / "host-b"),
                  "--out", str(sandbox / "b")]),
            env={**os.environ, "LEARNPNP_IPC_DIR": str(sandbox / "ipc-b")}, stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True)
        try:
            # From the sandbox: `learnpnp` is the installed package, not this source tree.
            client = subprocess.run(on_b([sys.executable, "-c", CLIENT, endpoint, str(certs / "monitor")]),
                                    capture_output=True, text=True, timeout=120, cwd=sandbox)
        finally:
            a_out, a_err = host_a.communicate(timeout=120)
            b_out, b_err = host_b.communicate(timeout=120)
    assert client.returncode == 0, client.stderr
    assert host_a.returncode == 0, a_err
    assert host_b.returncode == 0, b_err
    heard = {int(sender): beat for sender, beat in json.loads(client.stdout).items()}
    run_id = json.loads((sandbox / "b" / "summary.json").read_text())["run_id"]
    assert set(heard) == {0, 100}, "the agent's (host B) and the world's (host A) heartbeats"
    tag = rf"learnpnp::Heartbeat;{PROTOCOL_VERSION};\d+"
    assert all(re.fullmatch(tag, beat["tag"]) for beat in heard.values()), heard
    assert all(beat["run_id"] == run_id and beat["pid"] > 0 for beat in heard.values())
    summary = json.loads((sandbox / "a" / "summary.json").read_text())
    assert summary["complete"] and summary["experiment"]["final_greedy_mean"] == -4.0
    link = summary["link"]
    assert link["security"] == "mutual-tls-quic"
    assert link["refused"]["access_denied"] >= 2, "the monitor's two publications were denied and counted"
