"""Where the tools find the robots: the repository this package lives in (config/, launch/,
report/) and its scripts/ folder (the commands a runner starts as processes)."""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__)))))
SCRIPTS = os.path.join(ROOT, 'scripts')
