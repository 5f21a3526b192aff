"""The `winder` executable (and `python -m winder`): the command line of winder.cli.

Importing numpy and scipy takes a second or two; a TERM or Ctrl-C in that time ends winder with one
`Error:` line and exit 143 / 130 rather than a traceback (nothing is written yet). Once winder.cli
runs, it handles both itself (winder.app.interrupts).
"""

from __future__ import annotations

import os
import signal
import sys


def _starting(signum: int, frame) -> None:
    os.write(2, f"Error: interrupted by {signal.Signals(signum).name} while starting\n".encode())
    os._exit(128 + signum)


def main() -> None:
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, _starting)
    from winder.cli import main as cli  # noqa: PLC0415 - after the handlers: the import takes a while

    cli()


if __name__ == "__main__":
    main()
