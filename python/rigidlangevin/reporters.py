"""A reporter for openmm.app.Simulation that writes the temperatures of rigid-body dynamics."""
import openmm.unit as unit

from .core import RigidLangevinIntegrator


class RigidBodyTemperatureReporter(object):
    """Writes the translational, rotational and total temperatures of a simulation run with
    RigidLangevinIntegrator, as comma-separated values: step, time (ps), then the temperatures (K).
    Rigid-water integrators are known to break equipartition between translation and rotation at
    large steps; this shows it.

    Parameters
    ----------
    file : str or file-like
        A file name to write to, or an open file.
    reportInterval : int
        The interval (in steps) at which to report.
    append : bool
        Append to an existing file instead of starting a new one with a header.
    """

    def __init__(self, file, reportInterval, append=False):
        self._reportInterval = reportInterval
        self._openedFile = isinstance(file, str)
        self._out = open(file, 'a' if append else 'w') if self._openedFile else file
        self._wroteHeader = append

    def describeNextReport(self, simulation):
        steps = self._reportInterval - simulation.currentStep % self._reportInterval
        return {'steps': steps, 'periodic': None, 'include': []}

    def report(self, simulation, state):
        integrator = RigidLangevinIntegrator.cast(simulation.integrator)
        if not self._wroteHeader:
            print('#"Step","Time (ps)","Translational temperature (K)","Rotational temperature (K)","Temperature (K)"', file=self._out)
            self._wroteHeader = True
        values = [integrator.computeTranslationalTemperature(), integrator.computeRotationalTemperature(), integrator.computeSystemTemperature()]
        print(','.join([str(simulation.currentStep), '%g' % state.getTime().value_in_unit(unit.picosecond)] +
                       ['%.4f' % v.value_in_unit(unit.kelvin) for v in values]), file=self._out)
        if hasattr(self._out, 'flush'):
            self._out.flush()

    def __del__(self):
        if getattr(self, '_openedFile', False):
            self._out.close()
