"""Stage 8, app: what the CLI runs, as library calls.

jobs (one job and batches in processes, atomic outputs), regress (samples against references),
compare (output comparison within tolerances).

May import: every earlier stage; never click (only winder.cli talks to the user).
"""
