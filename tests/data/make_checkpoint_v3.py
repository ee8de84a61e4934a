"""Wrote checkpoint_v3.chk and checkpoint_v3_after.npy with the plugin at commit 4add0d7, whose
checkpoints were format 3 (no checksum): test_checkpoints.py must read that format correctly.
Eight asymmetric bodies (tests/test_state_restore.build) with friction on the Reference platform:
20 steps, the checkpoint, then 10 more steps whose positions a restored Context must reproduce.
Kept to show how the files were made; run with that commit's plugin installed, it writes them again."""
import pathlib
import sys

import numpy as np
import openmm as mm

import rigidlangevin as rl

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from test_state_restore import build  # noqa: E402


def scene():
    system, integrator, positions = build('asymmetric')
    integrator.setViscosity(0.89*rl.centipoise)
    integrator.setRandomNumberSeed(17)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    return context, integrator, positions


if __name__ == '__main__':
    context, integrator, positions = scene()
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 5)
    integrator.step(20)
    (HERE/'checkpoint_v3.chk').write_bytes(context.createCheckpoint())
    integrator.step(10)
    np.save(HERE/'checkpoint_v3_after.npy', context.getState(getPositions=True, getVelocities=True).getPositions(asNumpy=True)._value)
