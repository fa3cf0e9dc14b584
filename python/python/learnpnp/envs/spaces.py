"""The spaces the Keepaway environments share."""

from __future__ import annotations

from typing import Tuple

import numpy as np
from gymnasium import spaces

#: Stone, Sutton and Kuhlmann's 13 state variables, in the papers' order.
STATE_VARIABLES: Tuple[str, ...] = (
    "dist(K1,C)",
    "dist(K1,K2)",
    "dist(K1,K3)",
    "dist(K1,T1)",
    "dist(K1,T2)",
    "dist(K2,C)",
    "dist(K3,C)",
    "dist(T1,C)",
    "dist(T2,C)",
    "min dist(K2,T)",
    "min dist(K3,T)",
    "min ang(K2,K1,T)",
    "min ang(K3,K1,T)",
)

#: The actions, by index.
ACTIONS: Tuple[str, ...] = ("hold", "pass-nearest", "pass-second-nearest")


def observation_space(field_length: float, field_width: float) -> spaces.Box[np.float32]:
    """The 13 state variables: distances and angles are never negative; the
    bound (four times the region's half-perimeter, at least 180 degrees) is
    one no distance on the field reaches."""
    high = max(180.0, 4.0 * (field_length + field_width))
    return spaces.Box(low=0.0, high=high, shape=(len(STATE_VARIABLES),), dtype=np.float32)


def action_space() -> spaces.Discrete[np.int64]:
    """Hold, pass to the nearest teammate, pass to the second nearest."""
    return spaces.Discrete(len(ACTIONS))
