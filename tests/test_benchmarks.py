"""The benchmarks stay runnable: each runs in its quick form."""
import csv
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_speed_vs_error_study_quick(tmp_path):
    result = subprocess.run([sys.executable, str(ROOT/'benchmarks'/'speed_vs_error'/'study.py'), '--quick', '--parts', 's1', '--out', str(tmp_path)],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    rows = list(csv.DictReader(open(tmp_path/'results.csv')))
    assert {r['integrator'] for r in rows} == {'ExactFlow', 'BAOAB', 'Original'}
    assert all(float(r['ns/day']) > 0 for r in rows if r['status'] == 'ok')
    assert any(r['status'].startswith('refused') for r in rows if r['integrator'] == 'Original')
    assert (tmp_path/'table.md').exists() and (tmp_path/'error_vs_speed_s1_0.003P.png').stat().st_size > 10000
