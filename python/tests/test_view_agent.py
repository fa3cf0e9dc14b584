"""A PlanAgent watched live: `view=` serves the page on loopback and
`record_mcap=` records the feed (read back with the `mcap` package)."""

import gc
import json
import urllib.request
from collections import Counter

from mcap.reader import make_reader

import learnpnp


def play(agent, episodes):
    for _ in range(episodes):
        while (name := agent.act({"Open": False})) is not None:
            agent.reward(1.0 if name == "Left" else 0.0)
        agent.end_episode()


def test_an_agent_without_a_view_serves_nothing(doors):
    assert learnpnp.PlanAgent(doors(), seed=1).view_address is None


def test_a_watched_agent_serves_the_page_and_records_its_choices(sandbox, doors):
    recording = sandbox / "agent.mcap"
    agent = learnpnp.PlanAgent(doors(), algo="eps-sosmc", seed=3, view="127.0.0.1:0", record_mcap=str(recording))
    host, port = agent.view_address.rsplit(":", 1)
    assert host == "127.0.0.1" and int(port) > 0
    with urllib.request.urlopen(f"http://{agent.view_address}/", timeout=10) as page:
        assert b"<html" in page.read()
    play(agent, 50)
    del agent
    gc.collect()
    assert recording.exists() and not (sandbox / "agent.mcap.part").exists()
    counts, choices, plans = Counter(), [], []
    with open(recording, "rb") as f:
        for _, channel, message in make_reader(f).iter_messages():
            counts[channel.topic] += 1
            record = json.loads(message.data)
            if channel.topic == "/learnpnp/choice":
                choices.append(record)
            elif channel.topic == "/learnpnp/plan":
                plans.append(record)
    assert len(plans) == 1 and plans[0]["plan"] == "doors"
    assert counts["/learnpnp/episode"] == 50
    # Every choice is sent; its options are the plan's, and learning shows in their counts.
    assert len(choices) == 50
    labels = {place["label"] for place in plans[0]["places"]}
    assert all(c["choice_point"] in labels and len(c["options"]) == 2 for c in choices)
    assert any(o["updates"] > 0 and o["value"] is not None for o in choices[-1]["options"])
