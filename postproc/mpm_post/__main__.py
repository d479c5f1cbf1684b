"""python -m mpm_post: see mpm_post.cli."""

import sys

from .cli import main

sys.exit(main())
