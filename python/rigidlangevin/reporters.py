"""Reporters for openmm.app.Simulation: the temperatures of rigid-body dynamics, and every body's state."""
import openmm.unit as unit

from .core import RigidBrownianIntegrator, RigidLangevinIntegrator


class _CsvReporter(object):
    """What both reporters share: the file (a name, opened here, or an open file), the interval, and
    a header line written once unless appending."""

    def __init__(self, file, reportInterval, append):
        self._reportInterval = reportInterval
        self._openedFile = isinstance(file, str)
        self._out = open(file, 'a' if append else 'w', encoding='utf-8') if self._openedFile else file
        self._wroteHeader = append

    def describeNextReport(self, simulation):
        steps = self._reportInterval - simulation.currentStep % self._reportInterval
        return {'steps': steps, 'periodic': None, 'include': []}

    @staticmethod
    def _time(state):
        """The state's time in ps, to twelve significant digits: a step of 2 fs stays visible up to
        100 us ('%g' printed 10000.002 ps as 10000)."""
        return '%.12g' % state.getTime().value_in_unit(unit.picosecond)

    def _write(self, header, lines):
        if not self._wroteHeader:
            print(header, file=self._out)
            self._wroteHeader = True
        for line in lines:
            print(line, file=self._out)
        if hasattr(self._out, 'flush'):
            self._out.flush()

    def __del__(self):
        if getattr(self, '_openedFile', False):
            self._out.close()


class RigidBodyTemperatureReporter(_CsvReporter):
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
        super().__init__(file, reportInterval, append)

    def report(self, simulation, state):
        integrator = RigidLangevinIntegrator.cast(simulation.integrator)
        values = [integrator.computeTranslationalTemperature(), integrator.computeRotationalTemperature(), integrator.computeSystemTemperature()]
        self._write('#"Step","Time (ps)","Translational temperature (K)","Rotational temperature (K)","Temperature (K)"',
                    [','.join([str(simulation.currentStep), self._time(state)] +
                              ['%.4f' % v.value_in_unit(unit.kelvin) for v in values])])


class RigidBodyStateReporter(_CsvReporter):
    """Writes every rigid body's state (getRigidBodyStates() of a RigidLangevinIntegrator or a
    RigidBrownianIntegrator, whose velocities are the last step's displacement over the step) as comma-separated
    values, one row per body per report, for numpy (numpy.genfromtxt(file, delimiter=',', names=True))
    or pandas (pandas.read_csv(file)). The header names the columns:

        step, time_ps, body,
        x_nm, y_nm, z_nm                    the centre of mass (unwrapped: it moves on across a periodic box)
        a11 ... a33                         the orientation A (body frame to lab, row-major; its columns are
                                            the principal axes in the lab frame)
        vx_nm_ps, vy_nm_ps, vz_nm_ps        the centre-of-mass velocity
        wx_rad_ps, wy_rad_ps, wz_rad_ps     the angular velocity (lab frame)

    A particle at body-frame coordinates b (integrator.getRigidBodyCoordinates(body)) is at x + A b.
    The velocities are synchronous with the positions: under ExactFlow a body pulled by a constant force
    F averages its drift velocity (F/(m gamma) for a sphere) at any step and friction. A State's velocities
    are the integrator's stored ones instead, which average gamma h/(exp(gamma h) - 1) of the drift (see
    RigidLangevinIntegrator.getRigidBodyStates()): measure sedimentation velocities from this file.

    Parameters
    ----------
    file : str or file-like
        A file name to write to, or an open file.
    reportInterval : int
        The interval (in steps) at which to report.
    bodies : sequence of int, optional
        The bodies to write (default: all).
    append : bool
        Append to an existing file instead of starting a new one with a header.
    """

    COLUMNS = (['step', 'time_ps', 'body', 'x_nm', 'y_nm', 'z_nm'] + [f'a{i}{j}' for i in (1, 2, 3) for j in (1, 2, 3)] +
               ['vx_nm_ps', 'vy_nm_ps', 'vz_nm_ps', 'wx_rad_ps', 'wy_rad_ps', 'wz_rad_ps'])

    def __init__(self, file, reportInterval, bodies=None, append=False):
        super().__init__(file, reportInterval, append)
        self._bodies = None if bodies is None else [int(b) for b in bodies]

    def report(self, simulation, state):
        integrator = _rigid_body_integrator(simulation.integrator)
        states = integrator.getRigidBodyStates()
        centers = states.centers.value_in_unit(unit.nanometer)
        velocities = states.velocities.value_in_unit(unit.nanometer/unit.picosecond)
        angular = states.angularVelocities.value_in_unit(unit.radian/unit.picosecond)
        time = self._time(state)
        lines = []
        for b in (range(len(centers)) if self._bodies is None else self._bodies):
            values = list(centers[b])+list(states.orientations[b].ravel())+list(velocities[b])+list(angular[b])
            lines.append(','.join([str(simulation.currentStep), time, str(b)]+['%.10g' % v for v in values]))
        self._write(','.join(self.COLUMNS), lines)


def _rigid_body_integrator(integrator):
    """The simulation's integrator as the rigid-body integrator it is (Langevin or Brownian)."""
    if RigidBrownianIntegrator.isinstance(integrator):
        return RigidBrownianIntegrator.cast(integrator)
    return RigidLangevinIntegrator.cast(integrator)
