"""CTest's entry to the pytest suite: skips (exit 77) with a message when pytest or numpy is
missing, else runs every test of this folder and returns pytest's exit status."""
import os
import sys

try:
    import numpy  # noqa: F401
    import pytest
except ImportError as e:
    print(f"python tests skipped: {e} (scripts/install-deps.sh installs python3-pytest and "
          "python3-numpy)")
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", here] + sys.argv[1:]))
