"""How many points a path gets: the default, the coarsest solver level, the least its rounds allow, and
the hint when a solve had too few (docs/math/03-newton.md). A helix needs its points per round, not per path."""

from __future__ import annotations

import math

from winder.config.winding import DEFAULT_POINTS
from winder.errors import ConfigError

COARSEST = 31  # interior points of the coarsest level
POINTS_PER_ROUND = 24  # the coarsest level keeps this many points per round of a helix
DEFAULT_PER_ROUND = 48  # the default n keeps at least this many points per round of a helix
# Fewer segments than this per round let a chord span over a third of a turn: it cuts deep across the
# mandrel, and the shortest chain need not follow the surface at all (200 points for 100 rounds of the
# elbow sample "converged" to a 72.9 m length where the fiber is 25.1 m).
MIN_SEGMENTS_PER_ROUND = 3
MAX_POINTS = 1_000_000  # the solver holds ~1 kB per point: beyond this, refuse instead of swapping


def coarsest_points(rounds: float) -> int:
    """Interior points of the coarsest level for a path sweeping this many rounds."""
    return max(COARSEST, int(POINTS_PER_ROUND * rounds))


def default_points(rounds: float) -> int:
    """The default n: DEFAULT_POINTS, and at least DEFAULT_PER_ROUND per round swept."""
    return max(DEFAULT_POINTS, int(math.ceil(DEFAULT_PER_ROUND * rounds)))


def check_points(n: int, rounds: float, max_points: int) -> None:
    """Refuse n interior points for a path sweeping this many rounds (ConfigError on `points`): fewer
    than 1, more than max_points, or fewer segments than MIN_SEGMENTS_PER_ROUND a round."""
    if n < 1:
        raise ConfigError(f"must be >= 1, got {n}", key_path="points")
    if n > max_points:
        raise ConfigError(f"at most {max_points} (memory and time grow with n), got {n}", key_path="points")
    if n + 1 < MIN_SEGMENTS_PER_ROUND * rounds:
        raise ConfigError(f"must be at least {math.ceil(MIN_SEGMENTS_PER_ROUND * rounds) - 1} for a path of "
                          f"{rounds:.4g} rounds: with fewer, a segment spans over a third of a turn and cuts across "
                          f"the mandrel (an accurate length wants {POINTS_PER_ROUND} per round: "
                          f"{math.ceil(POINTS_PER_ROUND * rounds)}), got {n}", key_path="points")


def too_few_hint(n: int, rounds: float) -> str:
    """What to do when a solve at n points over this many rounds did not converge ('' if n is enough)."""
    if n >= POINTS_PER_ROUND * rounds:
        return ""
    return (f"; {n} points are fewer than {POINTS_PER_ROUND} per round for {rounds:.3g} rounds: raise "
            f"--points to at least {math.ceil(POINTS_PER_ROUND * rounds)}")
