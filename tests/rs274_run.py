"""LinuxCNC's own interpreter, `rs274 -g` (Debian package linuxcnc-uspace), run on a program text: its
canonical calls (STRAIGHT_FEED, SET_FEED_RATE, SET_AUX_OUTPUT_VALUE, SET_G92_OFFSET, ...) one per line."""

from __future__ import annotations

import fcntl
import shutil
import subprocess
import tempfile
from pathlib import Path

RS274 = shutil.which("rs274")
LOCK = Path(tempfile.gettempdir()) / "winder-tests-rs274.lock"


def run_rs274(path: Path, text: str) -> str:
    """rs274 -g of `text` (written to `path`): its standard output; the interpreter must accept it."""
    path.write_text(text)
    # One rs274 at a time on the machine: two at once (two test runs side by side) were seen to kill one
    # with SIGBUS, the interpreter sharing state between its processes.
    with open(LOCK, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        result = subprocess.run([RS274, "-g", str(path)], input="", capture_output=True, text=True, timeout=120,
                                check=False)
    assert result.returncode == 0, (result.stdout[-400:], result.stderr[-400:])
    return result.stdout
