"""Installing what the harness compares against, when it is missing.

- POV-Ray: Debian's `povray` package, through apt-get (as root, or through sudo).
- Embree's Python bindings: PyPI's `embreex` (it brings numpy). When the running Python cannot
  import them, a virtual environment in benches/compare/.venv gets them and the harness starts
  again under its interpreter, so the system's Python is left alone.
"""

import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VENV = os.path.join(HERE, ".venv")
VENV_PYTHON = os.path.join(VENV, "bin", "python")


def _run(command):
    print("compare: running", " ".join(command), file=sys.stderr)
    subprocess.run(command, check=True)


def ensure_povray(allow):
    """Makes sure `povray` is on PATH."""
    if shutil.which("povray"):
        return
    if not allow:
        raise SystemExit("compare: povray not found (install Debian's `povray`, or drop --no-install)")
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    _run(sudo + ["apt-get", "update"])
    _run(sudo + ["apt-get", "install", "-y", "povray"])
    if not shutil.which("povray"):
        raise SystemExit("compare: apt-get installed povray but it is not on PATH")


def python_has_embreex():
    try:
        import embreex  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        return False
    return True


def ensure_embreex(allow, argv):
    """Returns normally when this Python can import embreex and numpy; otherwise installs them
    into .venv and re-executes `argv` under that venv's Python (never returns then)."""
    if python_has_embreex():
        return
    # A venv's python is a link to the system interpreter, so compare prefixes, not executables.
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        raise SystemExit("compare: embreex does not import even in %s" % VENV)
    if not allow:
        raise SystemExit("compare: embreex is not importable (pip install embreex, or drop --no-install)")
    if not os.path.exists(VENV_PYTHON):
        _run([sys.executable, "-m", "venv", VENV])
    _run([VENV_PYTHON, "-m", "pip", "install", "embreex"])
    os.execv(VENV_PYTHON, [VENV_PYTHON] + argv)
