"""The examples stay runnable: each is run briefly."""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_bent_trimers_example(platform):
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'bent_trimers.py'), '--bodies', '60', '--steps', '200', '--report', '100',
                             '--platform', platform.name], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    def numbers(line):
        try:
            return [float(v) for v in line.split()]
        except ValueError:
            return None
    # Report lines: time, T_trans, T_rot, T, potential, kinetic, ns/day; temperatures physical.
    rows = [numbers(l) for l in result.stdout.splitlines() if numbers(l) is not None and len(l.split()) == 7]
    assert len(rows) == 2
    for row in rows:
        assert 100 < row[1] < 600 and 100 < row[2] < 600


def test_readme_python_quick_start():
    readme = (ROOT/'README.md').read_text()
    code = readme.split('```python\n', 1)[1].split('```', 1)[0]
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert 'K' in result.stdout
