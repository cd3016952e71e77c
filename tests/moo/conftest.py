import sys
from pathlib import Path

# Make the local helper module importable regardless of pytest's import mode.
sys.path.insert(0, str(Path(__file__).parent))
