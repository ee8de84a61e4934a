"""Memory bandwidth of RigidLangevinIntegrator on a CUDA GPU, as a fraction of the device's peak.

The integrator alone (force-free rigid waters, ExactFlow, as in integrator_cost.py) moves little
arithmetic per byte, so its speed limit is memory bandwidth. Nsight Compute (ncu) profiles the
kernels of a few steady-state steps of 1e6 bodies and reports, per kernel, DRAM bytes, duration and
DRAM throughput as a percentage of the device's peak; the table gives the duration-weighted
fraction over a whole step, and the bytes per body-step divided by the unprofiled wall time per
step (the bandwidth the integrator achieves in a real run, launch gaps included).

    python benchmarks/platforms/gpu_bandwidth.py [--bodies 1000000] [--precision mixed]

Needs a CUDA GPU and ncu on the PATH (where either is missing it says so and writes nothing).
"""
import argparse
import csv
import io
import os
import shutil
import subprocess
import sys

import openmm as mm
import openmm.unit as unit

from benchmark_utils import platform_status, time_per_step, write_table
from integrator_cost import build

STEPS = 12             # steps run under the profiler; the last full ones are measured
MEASURED_STEPS = 8
# ncu's unit names (they changed between versions) in bytes, seconds and percent.
UNITS = {'byte': 1, 'Kbyte': 1e3, 'Mbyte': 1e6, 'Gbyte': 1e9, 'B': 1, 'KB': 1e3, 'MB': 1e6, 'GB': 1e9,
         'nsecond': 1e-9, 'usecond': 1e-6, 'msecond': 1e-3, 'second': 1, 'ns': 1e-9, 'us': 1e-6, 'ms': 1e-3, 's': 1,
         '%': 1}
METRICS = ['gpu__time_duration.sum', 'dram__bytes_read.sum', 'dram__bytes_write.sum',
           'dram__throughput.avg.pct_of_peak_sustained_elapsed']


def make_context(bodies, precision):
    system, integrator, positions = build(bodies, True)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CUDA'), {'Precision': precision})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    return integrator, context


def workload(bodies, precision):
    """The program ncu profiles: a context and a few steps."""
    integrator, context = make_context(bodies, precision)
    integrator.step(STEPS)
    context.getState(getPositions=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--bodies', type=int, default=1000000)
    parser.add_argument('--precision', default='mixed', choices=['single', 'mixed', 'double'])
    parser.add_argument('--workload', action='store_true', help='internal: the program ncu profiles')
    parser.add_argument('--name', default='gpu_bandwidth')
    args = parser.parse_args()
    if args.workload:
        workload(args.bodies, args.precision)
        return
    status = platform_status('CUDA')
    if status is not None or shutil.which('ncu') is None:
        print(f'gpu_bandwidth: nothing measured: {status or "ncu (Nsight Compute) is not on the PATH"}')
        return

    # Wall time per step without the profiler.
    integrator, context = make_context(args.bodies, args.precision)
    seconds = time_per_step(integrator, context, 50)
    del context, integrator

    # Profile every launch (ncu replays each kernel to read its counters), then keep the launches of
    # the last MEASURED_STEPS full steps: each step launches the body-step kernel exactly once.
    profile = subprocess.run(['ncu', '--target-processes', 'all', '--csv', '--metrics', ','.join(METRICS),
                              sys.executable, os.path.abspath(__file__), '--workload', '--bodies', str(args.bodies),
                              '--precision', args.precision], capture_output=True, encoding='utf-8')
    launches = {}
    for row in csv.DictReader(io.StringIO(csv_part(profile.stdout))):
        value = float(row['Metric Value'].replace(',', ''))
        scale = UNITS[row['Metric Unit']]
        launches.setdefault(int(row['ID']), {'name': row['Kernel Name'].split('(')[0]})[row['Metric Name']] = value*scale
    order = sorted(launches)
    step_launches = [i for i, id in enumerate(order) if launches[id]['name'].startswith('step')]
    if len(step_launches) < MEASURED_STEPS+1:
        print('gpu_bandwidth: ncu returned too few steps:\n'+profile.stdout[-3000:]+profile.stderr[-3000:])
        return
    window = [launches[id] for id in order[step_launches[-MEASURED_STEPS-1]:step_launches[-1]]]
    per_step = len(window)/MEASURED_STEPS  # the random numbers are generated every other step
    by_name = {}
    for m in window:
        s = by_name.setdefault(m['name'], {'launches': 0, 'time': 0.0, 'bytes': 0.0, 'pct_time': 0.0})
        s['launches'] += 1
        s['time'] += m['gpu__time_duration.sum']
        s['bytes'] += m['dram__bytes_read.sum']+m['dram__bytes_write.sum']
        s['pct_time'] += m['dram__throughput.avg.pct_of_peak_sustained_elapsed']*m['gpu__time_duration.sum']
    total_time = sum(s['time'] for s in by_name.values())
    total_bytes = sum(s['bytes'] for s in by_name.values())
    weighted = sum(s['pct_time'] for s in by_name.values())/total_time
    peak = total_bytes/total_time/(weighted/100)  # bytes/s at 100% of peak, as ncu counts it
    rows = []
    for name, s in sorted(by_name.items(), key=lambda item: -item[1]['time']):
        rows.append({'kernel': name, 'launches': s['launches'], 'us_per_step': f"{1e6*s['time']/MEASURED_STEPS:.4g}",
                     'bytes_per_body_step': f"{s['bytes']/MEASURED_STEPS/args.bodies:.4g}",
                     'dram_pct_of_peak': f"{s['pct_time']/s['time']:.1f}"})
    bytes_per_step = total_bytes/MEASURED_STEPS
    rows.append({'kernel': 'all kernels of a step (profiled)', 'launches': per_step,
                 'us_per_step': f'{1e6*total_time/MEASURED_STEPS:.4g}',
                 'bytes_per_body_step': f'{bytes_per_step/args.bodies:.4g}', 'dram_pct_of_peak': f'{weighted:.1f}'})
    rows.append({'kernel': 'whole step, unprofiled wall time', 'launches': per_step, 'us_per_step': f'{1e6*seconds:.4g}',
                 'bytes_per_body_step': f'{bytes_per_step/args.bodies:.4g}',
                 'dram_pct_of_peak': f'{100*bytes_per_step/seconds/peak:.1f}'})
    print(f'CUDA {args.precision}, {args.bodies} bodies; peak DRAM bandwidth as ncu counts it: {peak/1e12:.2f} TB/s')
    write_table(args.name, ['kernel', 'launches', 'us_per_step', 'bytes_per_body_step', 'dram_pct_of_peak'], rows)


def csv_part(text):
    """ncu prints its own lines (==PROF==) before the CSV; keep from the header on."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith('"ID"'):
            return '\n'.join(lines[i:])
    return ''


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
