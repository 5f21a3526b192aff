"""`python -m winder.cli`: the command line without the executable's early signal handlers (winder.__main__)."""

from winder.cli import main

main()
