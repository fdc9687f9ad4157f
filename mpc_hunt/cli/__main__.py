"""`python -m mpc_hunt.cli`: the command line, as `mpc-hunt`."""

import sys

from mpc_hunt.cli.commands import main

sys.exit(main())
