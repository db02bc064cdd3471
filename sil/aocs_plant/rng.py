"""Seeded, repeatable noise for the plant.

Every random channel gets its own numpy Generator derived from the scenario
seed and a fixed channel index (SeedSequence spawn key), so enabling or
disabling one channel never shifts the numbers another channel draws, and the
same seed gives the same run bit for bit. Samples are generated in blocks with
numpy (vectorised) and handed out as plain float tuples for the hot path.
"""
from __future__ import annotations

import numpy as np

# Fixed channel indices: never renumber (it would change every seeded run).
CHANNELS = {
    "attitude": 0,
    "rate": 1,
    "position": 2,
    "velocity": 3,
    "wheel_torque": 4,
    "tachometer": 5,
}


def claim(channel: str, index: int) -> None:
    """Reserve a fixed stream index for a channel (a sensor module's, at import). The existing channels
    keep their indices above; a new one takes an index no other channel has, never to be renumbered."""
    index = int(index)
    if channel in CHANNELS:
        if CHANNELS[channel] != index:
            raise ValueError(f"noise channel {channel!r} has index {CHANNELS[channel]}, not {index}")
        return
    taken = {i: c for c, i in CHANNELS.items()}
    if index in taken or index < 0:
        raise ValueError(f"noise channel {channel!r}: index {index} is negative or taken by {taken.get(index)!r}")
    CHANNELS[channel] = index


def generator(seed: int, channel: str) -> np.random.Generator:
    """Independent Generator for one named channel of a seeded run."""
    ss = np.random.SeedSequence(entropy=int(seed), spawn_key=(CHANNELS[channel],))
    return np.random.Generator(np.random.PCG64(ss))


class NormalStream:
    """Zero-mean white Gaussian vectors (width components, 3 by default) with standard deviation std."""

    def __init__(self, seed: int, channel: str, std: float, block: int = 4096, width: int = 3):
        self._gen = generator(seed, channel)
        self._std = float(std)
        self._block = int(block)
        self._buf: list[list[float]] = []
        self._i = 0
        self._width = int(width)

    def next(self) -> tuple:
        if self._i >= len(self._buf):
            self._buf = (self._gen.standard_normal((self._block, self._width)) * self._std).tolist()
            self._i = 0
        v = self._buf[self._i]
        self._i += 1
        return tuple(v)
