import sys
from pathlib import Path

# The synthetic-record builders (viz_synthetic.py) live next to the tests.
sys.path.insert(0, str(Path(__file__).parent))
