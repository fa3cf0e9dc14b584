"""The live view's MCAP recording (`learnpnp experiment --record-mcap`) read
back with the `mcap` package, independently of the Rust writer."""

import json
import subprocess
from collections import Counter

from mcap.reader import make_reader

# One channel per kind of record of the feed (learnpnp-feed's CHANNELS).
FEED = {
    "/learnpnp/plan",
    "/learnpnp/marking",
    "/learnpnp/choice",
    "/learnpnp/reward",
    "/learnpnp/episode",
    "/learnpnp/curve",
    "/learnpnp/health",
    "/learnpnp/latency",
}


def test_a_recorded_run_reads_back_with_every_channel_of_an_in_process_run(learnpnp_cli, sandbox):
    recording = sandbox / "run.mcap"
    subprocess.run(
        [
            learnpnp_cli, "experiment", "parr-russell", "--algo", "eps-sosmc",
            "--runs", "1", "--episodes", "200", "--eval-every", "50",
            "--eval-episodes", "5", "--greedy-episodes", "5", "--threads", "1",
            "--out", str(sandbox / "out"), "--record-mcap", str(recording),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    assert not (sandbox / "run.mcap.part").exists()
    counts = Counter()
    plans, episodes = [], []
    with open(recording, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        # Chunks are written uncompressed, for the page's own reader.
        assert all(c.compression == "" for c in summary.chunk_indexes)
        for schema, channel, message in reader.iter_messages():
            assert channel.topic in FEED
            assert channel.message_encoding == "json"
            assert schema.encoding == "jsonschema"
            record = json.loads(message.data)
            counts[channel.topic] += 1
            if channel.topic == "/learnpnp/plan":
                plans.append(record)
            elif channel.topic == "/learnpnp/episode":
                episodes.append(record)
        stats = summary.statistics
        assert stats is not None
        by_channel = {summary.channels[i].topic: n for i, n in stats.channel_message_counts.items()}
    # An in-process run publishes every kind of record but the processes' health and latency.
    assert set(counts) == FEED - {"/learnpnp/health", "/learnpnp/latency"}
    assert dict(counts) == by_channel
    # One plan (one agent), and every episode of the protocol: 5 evaluation
    # episodes at 0, 50, ..., 200 learning episodes, the 200, the 5 greedy.
    assert len(plans) == 1 and plans[0]["places"]
    assert len(episodes) == 5 * 5 + 200 + 5
    assert sum(not e["evaluation"] for e in episodes) == 200
    assert counts["/learnpnp/curve"] == 5
