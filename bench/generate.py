"""Generate large, varied, valid OSC2 files for benchmarks and scale tests."""

from __future__ import annotations

import random

_ACTIONS = ("drive", "change_speed", "change_lane", "follow_lane", "assign_speed")
_PROFILES = ("none", "smooth", "asap", "constant")


def _scenario(rng: random.Random, i: int) -> list[str]:
    lines = [
        f"scenario follow_{i}:",
        "    hero: vehicle",
        "    npc: vehicle",
        f"    event near_{i}",
        f"    gap_{i}: length = {rng.randint(5, 40)}m * {rng.randint(1, 3)}",
        f"    top_{i}: speed = {rng.randint(30, 120)}kph",
        f"    keep(top_{i} < {rng.randint(121, 200)}kph and gap_{i} >= {rng.randint(1, 4)}m)",
        "    do serial:",
    ]
    members = []
    for j in range(rng.randint(2, 4)):
        kind = rng.random()
        if kind < 0.35:
            low, high = rng.randint(2, 5), rng.randint(6, 12)
            members += [
                f"        phase_{j}: parallel(duration: [{low}s..{high}s]):",
                "            hero.drive() with:",
                f"                speed({rng.randint(20, 90)}kph, at: start)",
                f"                lane({rng.randint(1, 3)})",
                "            npc.drive() with:",
                f"                position(distance: gap_{i}, behind: hero, at: start)",
            ]
        elif kind < 0.55:
            members.append(
                f"        hero.change_speed(target: {rng.randint(0, 80)}kph, "
                f"rate_profile: {rng.choice(_PROFILES)})"
            )
        elif kind < 0.7:
            members.append(f"        wait elapsed({rng.randint(1, 9)}.{rng.randint(0, 9)}s)")
        elif kind < 0.85:
            members += [
                f"        emit near_{i}",
                f"        wait hero.speed < {rng.randint(1, 20)}kph",
            ]
        else:
            members.append(
                f"        npc.change_lane(num_of_lanes: {rng.randint(1, 2)}, "
                f"side: {rng.choice(('left', 'right'))})"
            )
    return lines + members + [""]


def _struct(rng: random.Random, i: int) -> list[str]:
    return [
        f"# A pose with limits, number {i}.",
        f"struct pose_{i}:",
        f"    x: length = {rng.randint(0, 500)}m",
        "    y: length with:",
        f"        keep(default it in [{rng.randint(-20, 0)}m..{rng.randint(1, 20)}m])",
        f"    heading: angle = {rng.randint(0, 359)}deg",
        f"    def norm_{i}() -> length is expression x + y",
        "",
    ]


def _enum(rng: random.Random, i: int) -> list[str]:
    n = rng.randint(2, 6)
    members = ", ".join(f"m{i}_{k}" for k in range(n))
    return [f"enum kind_{i}: [{members}]", ""]


def _actor(rng: random.Random, i: int) -> list[str]:
    return [
        f"actor robot_{i} inherits vehicle:",
        f"    reach_{i}: length = {rng.randint(1, 9)}.{rng.randint(0, 9)}m",
        f"    var battery_{i}: float = {rng.random():.3f}",
        f"    event charged_{i}",
        "",
        f"action robot_{i}.dock_{i}:",
        f"    slot_{i}: uint = {rng.randint(0, 16)}",
        "",
    ]


def generate(lines: int, seed: int = 1) -> str:
    """An OSC2 file of about ``lines`` lines that checks without errors."""
    rng = random.Random(seed)
    out = ["import osc.standard", ""]
    makers = (_scenario, _scenario, _struct, _enum, _actor)
    i = 0
    while len(out) < lines:
        i += 1
        out += rng.choice(makers)(rng, i)
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    import sys

    print(generate(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000), end="")
