"""`python -m mpc_hunt.cli`: the command line, as `mpc-hunt`."""

import sys

from mpc_hunt.cli import main

sys.exit(main())
