/*
 * SWIG interface of the plugin's Python module. It imports OpenMM's own SWIG interface, so
 * RigidLangevinIntegrator derives from openmm.Integrator and works with openmm.Context,
 * openmm.XmlSerializer and openmm.app.Simulation. Arguments may be openmm.unit Quantities
 * (OpenMM's typemaps strip them to MD units; viscosities go through _units.viscosity_value first).
 */
%module(package="rigidlangevin") core

%include "factory.i"
%import(module="openmm") "swig/OpenMMSwigHeaders.i"

/* OpenMM's typemaps read numpy arrays directly when numpy is importable; they expect this helper. */
%header %{
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
namespace OpenMM {
int isNumpyAvailable() {
    static bool initialized = false;
    static bool available = false;
    if (!initialized) {
        initialized = true;
        available = (_import_array() >= 0);
        if (!available)
            PyErr_Clear();
    }
    return available;
}
}
using OpenMM::isNumpyAvailable;
%}
%include "swig/typemaps.i"

/* A vector of Vec3 returned by value (OpenMM's typemaps cover references): a list of openmm.Vec3. */
%typemap(out, fragment="Vec3_to_PyVec3") std::vector<Vec3> {
    const std::vector<OpenMM::Vec3>& vectors = $1;
    $result = PyList_New(vectors.size());
    for (int i = 0; i < (int) vectors.size(); i++)
        PyList_SET_ITEM($result, i, Vec3_to_PyVec3(vectors[i]));
}
%include <std_string.i>
%include <std_vector.i>

%{
#include "RigidLangevinIntegrator.h"
#include "RigidBrownianIntegrator.h"
#include "ResistanceTensor.h"
#include "CoupledResistance.h"
#include "StickyDipoleForce.h"
#include "OpenMM.h"
#include "OpenMMAmoeba.h"
#include "OpenMMDrude.h"
#include "openmm/RPMDIntegrator.h"
#include "openmm/RPMDMonteCarloBarostat.h"
#include "openmm/serialization/XmlSerializer.h"
#include <sstream>
// OpenMM's typemaps name the vector type Vec3.
using OpenMM::Vec3;
%}

%pythonbegin %{
import openmm
import openmm.unit as unit
from . import _units
%}

/* C++ exceptions become openmm.OpenMMException, as in OpenMM's own module. */
%exception {
    try {
        $action
    } catch (std::exception &e) {
        PyObject* mm = PyImport_AddModule("openmm");
        PyObject* openmmException = (mm == NULL ? NULL : PyObject_GetAttrString(mm, "OpenMMException"));
        PyErr_SetString(openmmException == NULL ? PyExc_Exception : openmmException, const_cast<char*>(e.what()));
        Py_XDECREF(openmmException);
        return NULL;
    }
}

namespace std {
    %template(vectori) vector<int>;
    %template(vectord) vector<double>;
}

/* Every class's and method's docstring is its header's documentation (python/doxygen_docs.py). */
%include "docstrings.i"
/* What the Python module adds. */
%feature("docstring") RigidLangevinPlugin::RigidLangevinIntegrator::isinstance "Whether an openmm.Integrator is a RigidLangevinIntegrator (then cast() gives it as one).";
%feature("docstring") RigidLangevinPlugin::RigidBrownianIntegrator::isinstance "Whether an openmm.Integrator is a RigidBrownianIntegrator (then cast() gives it as one).";
%feature("docstring") RigidLangevinPlugin::StickyDipoleForce::isinstance "Whether an openmm.Force is a StickyDipoleForce (then cast() gives it as one).";

namespace RigidLangevinPlugin {

class ResistanceTensor;

%pythonprepend RigidLangevinIntegrator::RigidLangevinIntegrator %{
    viscosity = _units.viscosity_value(viscosity)
%}
%pythonprepend RigidBrownianIntegrator::RigidBrownianIntegrator %{
    viscosity = _units.viscosity_value(viscosity)
%}
%pythonappend RigidBodyIntegrator::getTemperature %{
    val = unit.Quantity(val, unit.kelvin)
%}
%pythonappend RigidBodyIntegrator::getViscosity %{
    val = unit.Quantity(val, _units.md_viscosity)
%}
%pythonprepend RigidBodyIntegrator::setViscosity %{
    viscosity = _units.viscosity_value(viscosity)
%}
%pythonprepend RigidBodyIntegrator::addRigidBody %{
    particles = [int(p) for p in particles]
%}
%pythonappend RigidBodyIntegrator::getRigidBodyParticles %{
    val = tuple(val)
%}
%pythonappend RigidBodyIntegrator::getKrylovIterations %{
    val = tuple(val)
%}
%pythonprepend RigidBodyIntegrator::setBodyResistance %{
    tensor = _units.tensor_values(tensor)
%}
%pythonprepend RigidBodyIntegrator::setBodyBlobs %{
    blobRadii = _units.lengths_in_nm(blobRadii)
%}
%pythonappend RigidBodyIntegrator::getParticleRadius %{
    val = None if val < 0 else unit.Quantity(val, unit.nanometer)
%}
%pythonappend RigidBodyIntegrator::getRigidBodyCoordinates %{
    val = _units.vectors_in_nm(val)
%}
%pythonappend RigidLangevinIntegrator::computeSystemTemperature %{
    val = unit.Quantity(val, unit.kelvin)
%}
%pythonappend RigidLangevinIntegrator::computeTranslationalTemperature %{
    val = unit.Quantity(val, unit.kelvin)
%}
%pythonappend RigidLangevinIntegrator::computeRotationalTemperature %{
    val = unit.Quantity(val, unit.kelvin)
%}

%pythonprepend RigidBodyIntegrator::setWall %{
    height = _units.length_in_nm(height)
%}
%newobject RigidLangevinIntegrator::_clone;
%newobject RigidLangevinIntegrator::_deserialize;
%newobject RigidBrownianIntegrator::_clone;
%newobject RigidBrownianIntegrator::_deserialize;

/* What RigidLangevinIntegrator and RigidBrownianIntegrator share: bodies, hydrodynamics, read-outs. */
class RigidBodyIntegrator : public OpenMM::Integrator {
public:
    enum HydrodynamicSolver {
        AutomaticSolver = 0,
        DenseSolver = 1,
        KrylovSolver = 2,
        SpectralSolver = 3
    };
    double getTemperature() const;
    void setTemperature(double temp);
    double getViscosity() const;
    void setViscosity(double viscosity);
    int getRandomNumberSeed() const;
    void setRandomNumberSeed(int seed);
    int addRigidBody(const std::vector<int>& particles);
    int getNumRigidBodies() const;
    const std::vector<int>& getRigidBodyParticles(int index) const;
    void setBodyResistance(int index, const std::vector<double>& tensor, const Vec3& origin, const std::vector<Vec3>& referencePositions);
    void setBodyHydrodynamics(int index, const ResistanceTensor& model, const std::vector<Vec3>& referencePositions);
    void clearBodyResistance(int index);
    void setParticleRadius(int particle, double radius);
    double getParticleRadius(int particle) const;
    void setHydrodynamicInteractions(bool enabled);
    bool getHydrodynamicInteractions() const;
    std::vector<int> getKrylovIterations() const;
    void setHydrodynamicSolver(HydrodynamicSolver solver);
    HydrodynamicSolver getHydrodynamicSolver() const;
    void setHydrodynamicTolerance(double tolerance);
    double getHydrodynamicTolerance() const;
    void setKrylovMinBlobs(int blobs);
    int getKrylovMinBlobs() const;
    void setHydrodynamicMemoryBudget(double bytes);
    double getHydrodynamicMemoryBudget() const;
    void setBodyBlobs(int index, const std::vector<Vec3>& blobPositions, const std::vector<double>& blobRadii,
                      const std::vector<Vec3>& referencePositions);
    void clearBodyBlobs(int index);
    int getNumDegreesOfFreedom() const;
    std::vector<Vec3> getRigidBodyCoordinates(int index) const;
    int getNumBodyTypes() const;
    void setWall(double height);
    void clearWall();
protected:
    RigidBodyIntegrator(double temperature, double viscosity, double stepSize);
public:
    %extend {
        /* The explicit tensor of a body as (36 values, (x, y, z) origin, [(x, y, z)] reference positions), or None. */
        PyObject* _getBodyResistance(int index) const {
            std::vector<double> tensor;
            Vec3 origin;
            std::vector<Vec3> reference;
            if (!self->getBodyResistance(index, tensor, origin, reference))
                Py_RETURN_NONE;
            PyObject* values = PyList_New(36);
            for (int i = 0; i < 36; i++)
                PyList_SET_ITEM(values, i, PyFloat_FromDouble(tensor[i]));
            PyObject* positions = PyList_New(reference.size());
            for (int i = 0; i < (int) reference.size(); i++)
                PyList_SET_ITEM(positions, i, Py_BuildValue("(ddd)", reference[i][0], reference[i][1], reference[i][2]));
            return Py_BuildValue("(N(ddd)N)", values, origin[0], origin[1], origin[2], positions);
        }
        /* The blobs given to a body as ([(x, y, z)] centres, [radius], [(x, y, z)] reference positions), or None. */
        PyObject* _getBodyBlobs(int index) const {
            std::vector<Vec3> positions, reference;
            std::vector<double> radii;
            if (!self->getBodyBlobs(index, positions, radii, reference))
                Py_RETURN_NONE;
            PyObject* centres = PyList_New(positions.size());
            PyObject* blobRadii = PyList_New(radii.size());
            for (int i = 0; i < (int) positions.size(); i++) {
                PyList_SET_ITEM(centres, i, Py_BuildValue("(ddd)", positions[i][0], positions[i][1], positions[i][2]));
                PyList_SET_ITEM(blobRadii, i, PyFloat_FromDouble(radii[i]));
            }
            PyObject* referenceList = PyList_New(reference.size());
            for (int i = 0; i < (int) reference.size(); i++)
                PyList_SET_ITEM(referenceList, i, Py_BuildValue("(ddd)", reference[i][0], reference[i][1], reference[i][2]));
            return Py_BuildValue("(NNN)", centres, blobRadii, referenceList);
        }
        /* getRigidBodyStates() as four flat lists (3, 9, 3 and 3 values per body). */
        PyObject* _getRigidBodyStates() const {
            std::vector<Vec3> centers, velocities, angular;
            std::vector<double> orientations;
            self->getRigidBodyStates(centers, orientations, velocities, angular);
            PyObject* lists[4];
            const std::vector<Vec3>* vectors[4] = {&centers, NULL, &velocities, &angular};
            for (int k = 0; k < 4; k++) {
                if (k == 1) {
                    lists[k] = PyList_New(orientations.size());
                    for (int i = 0; i < (int) orientations.size(); i++)
                        PyList_SET_ITEM(lists[k], i, PyFloat_FromDouble(orientations[i]));
                    continue;
                }
                lists[k] = PyList_New(3*vectors[k]->size());
                for (int i = 0; i < (int) vectors[k]->size(); i++)
                    for (int j = 0; j < 3; j++)
                        PyList_SET_ITEM(lists[k], 3*i+j, PyFloat_FromDouble((*vectors[k])[i][j]));
            }
            return Py_BuildValue("(NNNN)", lists[0], lists[1], lists[2], lists[3]);
        }
        /* The wall's height (nm), or None without a wall. */
        PyObject* _getWall() const {
            double height;
            if (!self->getWall(height))
                Py_RETURN_NONE;
            return PyFloat_FromDouble(height);
        }
        %pythoncode %{
            def getRigidBodyStates(self):
                """The state of every rigid body (see the C++ getRigidBodyStates()): a RigidBodyStates with centers
                (N, 3) Quantity in nm (unwrapped across a periodic box), orientations (N, 3, 3) array A (columns the
                principal axes in the lab frame; a particle at body-frame coordinates b, getRigidBodyCoordinates(i),
                is at center + A b), velocities (N, 3) Quantity in nm/ps and angularVelocities (N, 3) Quantity in
                radians/ps (lab frame). The velocities are synchronous with the positions (a body pulled by a constant
                force averages its drift velocity), computed with the forces at the current positions; a State's
                velocities are the integrator's stored ones, whose mean under a force is not the drift."""
                return _units.rigid_body_states(self._getRigidBodyStates())

            def getBodyResistance(self, index):
                """The explicit resistance tensor of a body, as (6x6 numpy array, origin Vec3 in nm, the reference
                positions of the body's particles it belongs to as an (N, 3) array in nm), or None."""
                return _units.resistance_result(self._getBodyResistance(index))

            def getBodyBlobs(self, index):
                """The blobs given to a body with setBodyBlobs(), as (centres (N, 3) Quantity in nm, radii (N,)
                Quantity in nm, the reference positions of the body's particles they belong to (M, 3) Quantity
                in nm), or None if its particles with a radius are its blobs."""
                return _units.blobs_result(self._getBodyBlobs(index))

            def getWall(self):
                """The height of the no-slip wall (setWall()) as a Quantity in nm, or None without one."""
                height = self._getWall()
                return None if height is None else unit.Quantity(height, unit.nanometer)

        %}
    }
};

class RigidLangevinIntegrator : public RigidBodyIntegrator {
public:
    enum Scheme {
        ExactFlow = 0,
        BAOAB = 1,
        Original = 2
    };
    RigidLangevinIntegrator(double temperature, double viscosity, double stepSize);
    Scheme getScheme() const;
    void setScheme(Scheme scheme);
    double computeSystemTemperature();
    double computeTranslationalTemperature();
    double computeRotationalTemperature();
    void step(int steps);

    %extend {
        RigidLangevinPlugin::RigidLangevinIntegrator* _clone() const {
            return dynamic_cast<RigidLangevinPlugin::RigidLangevinIntegrator*>(OpenMM::XmlSerializer::clone<OpenMM::Integrator>(*self));
        }
        static RigidLangevinPlugin::RigidLangevinIntegrator* _deserialize(const std::string& xml) {
            std::stringstream stream(xml);
            return dynamic_cast<RigidLangevinPlugin::RigidLangevinIntegrator*>(OpenMM::XmlSerializer::deserialize<OpenMM::Integrator>(stream));
        }
        static RigidLangevinPlugin::RigidLangevinIntegrator& _cast(OpenMM::Integrator& integrator) {
            RigidLangevinPlugin::RigidLangevinIntegrator* result = dynamic_cast<RigidLangevinPlugin::RigidLangevinIntegrator*>(&integrator);
            if (result == NULL)
                throw OpenMM::OpenMMException("RigidLangevinIntegrator.cast: this Integrator is not a RigidLangevinIntegrator");
            return *result;
        }
        static bool isinstance(OpenMM::Integrator& integrator) {
            return dynamic_cast<RigidLangevinPlugin::RigidLangevinIntegrator*>(&integrator) != NULL;
        }
        %pythoncode %{
            @staticmethod
            def cast(integrator):
                """An openmm.Integrator that is a RigidLangevinIntegrator (from XmlSerializer.deserialize(), say)
                as one. The result keeps the original object alive."""
                if isinstance(integrator, RigidLangevinIntegrator):
                    return integrator
                result = RigidLangevinIntegrator._cast(integrator)
                result._source = integrator
                return result

            def __copy__(self):
                return self._clone()

            def __deepcopy__(self, memo):
                return self._clone()

            def __getstate__(self):
                return openmm.XmlSerializer.serialize(self)

            def __setstate__(self, state):
                self.this = RigidLangevinIntegrator._deserialize(state).this
        %}
    }
};

class RigidBrownianIntegrator : public RigidBodyIntegrator {
public:
    RigidBrownianIntegrator(double temperature, double viscosity, double stepSize);
    void step(int steps);

    %extend {
        RigidLangevinPlugin::RigidBrownianIntegrator* _clone() const {
            return dynamic_cast<RigidLangevinPlugin::RigidBrownianIntegrator*>(OpenMM::XmlSerializer::clone<OpenMM::Integrator>(*self));
        }
        static RigidLangevinPlugin::RigidBrownianIntegrator* _deserialize(const std::string& xml) {
            std::stringstream stream(xml);
            return dynamic_cast<RigidLangevinPlugin::RigidBrownianIntegrator*>(OpenMM::XmlSerializer::deserialize<OpenMM::Integrator>(stream));
        }
        static RigidLangevinPlugin::RigidBrownianIntegrator& _cast(OpenMM::Integrator& integrator) {
            RigidLangevinPlugin::RigidBrownianIntegrator* result = dynamic_cast<RigidLangevinPlugin::RigidBrownianIntegrator*>(&integrator);
            if (result == NULL)
                throw OpenMM::OpenMMException("RigidBrownianIntegrator.cast: this Integrator is not a RigidBrownianIntegrator");
            return *result;
        }
        static bool isinstance(OpenMM::Integrator& integrator) {
            return dynamic_cast<RigidLangevinPlugin::RigidBrownianIntegrator*>(&integrator) != NULL;
        }
        %pythoncode %{
            @staticmethod
            def cast(integrator):
                """An openmm.Integrator that is a RigidBrownianIntegrator (from XmlSerializer.deserialize(), say)
                as one. The result keeps the original object alive."""
                if isinstance(integrator, RigidBrownianIntegrator):
                    return integrator
                result = RigidBrownianIntegrator._cast(integrator)
                result._source = integrator
                return result

            def __copy__(self):
                return self._clone()

            def __deepcopy__(self, memo):
                return self._clone()

            def __getstate__(self):
                return openmm.XmlSerializer.serialize(self)

            def __setstate__(self, state):
                self.this = RigidBrownianIntegrator._deserialize(state).this
        %}
    }
};

/*
 * StickyDipoleForce. A site's parameters are keyword arguments in Python (Quantities or MD units:
 * nm, kJ/mol, e*nm), starting from a named model's (getModelParameters) where one is given.
 */
%newobject StickyDipoleForce::_clone;
%pythonappend StickyDipoleForce::getCutoffDistance %{
    val = unit.Quantity(val, unit.nanometer)
%}
%pythonappend StickyDipoleForce::getSwitchingDistance %{
    val = unit.Quantity(val, unit.nanometer)
%}

%header %{
/* A site's parameters from the 10 values Python passes, in the order of StickyDipoleForce.PARAMETER_NAMES. */
RigidLangevinPlugin::StickyDipoleForce::SiteParameters stickyDipoleSiteParameters(const std::vector<double>& v) {
    if (v.size() != 10)
        throw OpenMM::OpenMMException("StickyDipoleForce: a site has 10 parameters");
    RigidLangevinPlugin::StickyDipoleForce::SiteParameters p;
    p.sigma = v[0];
    p.epsilon = v[1];
    p.dipole = v[2];
    p.nu0 = v[3];
    p.rL = v[4];
    p.rU = v[5];
    p.nu0Prime = v[6];
    p.rLPrime = v[7];
    p.rUPrime = v[8];
    p.w0 = v[9];
    return p;
}
%}

class StickyDipoleForce : public OpenMM::Force {
public:
    enum NonbondedMethod {
        NoCutoff = 0,
        CutoffNonPeriodic = 1,
        CutoffPeriodic = 2
    };
    StickyDipoleForce();
    int getNumSites() const;
    int addExclusion(int site1, int site2);
    int getNumExclusions() const;
    void getExclusionSites(int index, int& OUTPUT, int& OUTPUT) const;
    NonbondedMethod getNonbondedMethod() const;
    void setNonbondedMethod(NonbondedMethod method);
    double getCutoffDistance() const;
    void setCutoffDistance(double distance);
    bool getUseSwitchingFunction() const;
    void setUseSwitchingFunction(bool use);
    double getSwitchingDistance() const;
    void setSwitchingDistance(double distance);
    double getReactionFieldDielectric() const;
    void setReactionFieldDielectric(double dielectric);
    bool usesPeriodicBoundaryConditions() const;

    %extend {
        static std::vector<double> _modelParameters(const std::string& model) {
            RigidLangevinPlugin::StickyDipoleForce::SiteParameters p = RigidLangevinPlugin::StickyDipoleForce::getModelParameters(model);
            return {p.sigma, p.epsilon, p.dipole, p.nu0, p.rL, p.rU, p.nu0Prime, p.rLPrime, p.rUPrime, p.w0};
        }
        int _addSite(int particle, int reference1, int reference2, const std::vector<double>& values) {
            return self->addSite(particle, reference1, reference2, stickyDipoleSiteParameters(values));
        }
        void _setSite(int index, int particle, int reference1, int reference2, const std::vector<double>& values) {
            self->setSiteParameters(index, particle, reference1, reference2, stickyDipoleSiteParameters(values));
        }
        std::vector<double> _getSite(int index) const {
            int particle, reference1, reference2;
            RigidLangevinPlugin::StickyDipoleForce::SiteParameters p;
            self->getSiteParameters(index, particle, reference1, reference2, p);
            return {(double) particle, (double) reference1, (double) reference2, p.sigma, p.epsilon, p.dipole, p.nu0, p.rL, p.rU,
                    p.nu0Prime, p.rLPrime, p.rUPrime, p.w0};
        }
        RigidLangevinPlugin::StickyDipoleForce* _clone() const {
            return dynamic_cast<RigidLangevinPlugin::StickyDipoleForce*>(OpenMM::XmlSerializer::clone<OpenMM::Force>(*self));
        }
        static RigidLangevinPlugin::StickyDipoleForce& _cast(OpenMM::Force& force) {
            RigidLangevinPlugin::StickyDipoleForce* result = dynamic_cast<RigidLangevinPlugin::StickyDipoleForce*>(&force);
            if (result == NULL)
                throw OpenMM::OpenMMException("StickyDipoleForce.cast: this Force is not a StickyDipoleForce");
            return *result;
        }
        static bool isinstance(OpenMM::Force& force) {
            return dynamic_cast<RigidLangevinPlugin::StickyDipoleForce*>(&force) != NULL;
        }
        %pythoncode %{
            PARAMETER_NAMES = ('sigma', 'epsilon', 'dipole', 'nu0', 'rL', 'rU', 'nu0Prime', 'rLPrime', 'rUPrime', 'w0')

            @staticmethod
            def getModelParameters(model):
                """The site parameters of a named model ('SSD', 'SSD1', 'SSD/E' or 'SSD/RF') as a dict of Quantities."""
                return _units.sticky_dipole_quantities(StickyDipoleForce._modelParameters(model))

            def addSite(self, particle, reference1, reference2, model=None, **parameters):
                """Add a site on a particle, framed by two reference particles of its molecule (z towards their
                midpoint, y along reference1 - reference2). Its parameters are a named model's, if given, with any
                of sigma, epsilon, dipole, nu0, rL, rU, nu0Prime, rLPrime, rUPrime, w0 given as keywords replacing
                them. Returns the index of the site."""
                return self._addSite(particle, reference1, reference2, _units.sticky_dipole_values(model, parameters))

            def setSiteParameters(self, index, particle, reference1, reference2, model=None, **parameters):
                """Replace a site (see addSite)."""
                self._setSite(index, particle, reference1, reference2, _units.sticky_dipole_values(model, parameters))

            def getSiteParameters(self, index):
                """(particle, reference1, reference2, dict of the site's parameters as Quantities)."""
                values = self._getSite(index)
                return int(values[0]), int(values[1]), int(values[2]), _units.sticky_dipole_quantities(values[3:])

            @staticmethod
            def cast(force):
                """An openmm.Force that is a StickyDipoleForce (from XmlSerializer.deserialize() or System.getForce())
                as one. The result keeps the original object alive."""
                if isinstance(force, StickyDipoleForce):
                    return force
                result = StickyDipoleForce._cast(force)
                result._source = force
                return result

            def __copy__(self):
                return self._clone()

            def __deepcopy__(self, memo):
                return self._clone()
        %}
    }
};

%pythonappend ResistanceTensor::getMatrix %{
    val = _units.matrix6(val)
%}
%pythonprepend ResistanceTensor::fromMatrix %{
    matrix = _units.tensor_values(matrix)
%}
%pythonappend ResistanceTensor::getOrigin %{
    val = unit.Quantity(val, unit.nanometer)
%}
%pythonappend ResistanceTensor::getCenterOfResistance %{
    val = unit.Quantity(val, unit.nanometer)
%}
%pythonappend ResistanceTensor::getCenterOfDiffusion %{
    val = unit.Quantity(val, unit.nanometer)
%}
%pythonprepend ResistanceTensor::getDiffusionTensor %{
    args = (args[0], _units.viscosity_value(args[1]))+tuple(args[2:])
%}
%pythonappend ResistanceTensor::getDiffusionTensor %{
    val = _units.matrix6(val)
%}
%pythonappend ResistanceTensor::roughShellBeads %{
    val = _units.vectors_in_nm(val)
%}
%pythonappend ResistanceTensor::spheroidRoughShellBeads %{
    val = _units.vectors_in_nm(val)
%}
%pythonappend ResistanceTensor::scaleBlobsToFriction %{
    val = _units.vectors_in_nm(val)
%}
%pythonprepend ResistanceTensor::rotated %{
    rotation = _units.rotation_values(rotation)
%}
%rename("explicit") ResistanceTensor::fromMatrix;

class ResistanceTensor {
public:
    ResistanceTensor();
    static ResistanceTensor fromMatrix(const std::vector<double>& matrix, const Vec3& origin);
    static ResistanceTensor sphere(double radius, const Vec3& center = Vec3());
    static ResistanceTensor ellipsoid(double a, double b, double c, const Vec3& center = Vec3());
    static ResistanceTensor spheroid(double a, double b, const Vec3& center = Vec3());
    static ResistanceTensor beads(const std::vector<Vec3>& positions, const std::vector<double>& radii, double correctionVolume = 0);
    static double beadVolume(const std::vector<double>& radii);
    static double unionVolume(const std::vector<Vec3>& positions, const std::vector<double>& radii);
    static ResistanceTensor roughShell(const std::vector<Vec3>& positions, const std::vector<double>& radii, double beadRadius);
    static std::vector<Vec3> roughShellBeads(const std::vector<Vec3>& positions, const std::vector<double>& radii, double beadRadius);
    static ResistanceTensor shellExtrapolated(const std::vector<Vec3>& positions, const std::vector<double>& radii,
                                              int maxBeads = 2000, int numResolutions = 6);
    static ResistanceTensor spheroidRoughShell(const std::vector<Vec3>& centers, const std::vector<Vec3>& axes, const std::vector<double>& a,
                                               const std::vector<double>& b, double beadRadius);
    static std::vector<Vec3> spheroidRoughShellBeads(const std::vector<Vec3>& centers, const std::vector<Vec3>& axes, const std::vector<double>& a,
                                                     const std::vector<double>& b, double beadRadius);
    static ResistanceTensor spheroidShellExtrapolated(const std::vector<Vec3>& centers, const std::vector<Vec3>& axes, const std::vector<double>& a,
                                                      const std::vector<double>& b, int maxBeads = 2000, int numResolutions = 6);
    static std::vector<Vec3> scaleBlobsToFriction(const std::vector<Vec3>& blobPositions, const std::vector<double>& blobRadii, const Vec3& center,
                                                  const ResistanceTensor& target);
    static ResistanceTensor freeDrainingBeads(const std::vector<Vec3>& positions, const std::vector<double>& radii);
    const Vec3& getOrigin() const;
    std::vector<double> getMatrix(const Vec3& origin) const;
    std::vector<double> getMatrix() const;
    Vec3 getCenterOfResistance() const;
    Vec3 getCenterOfDiffusion() const;
    std::vector<double> getDiffusionTensor(double temperature, double viscosity) const;
    std::vector<double> getDiffusionTensor(double temperature, double viscosity, const Vec3& origin) const;
    ResistanceTensor rotated(const std::vector<double>& rotation) const;
    ResistanceTensor translated(const Vec3& displacement) const;
    ResistanceTensor scaled(double factor) const;
    void validate(const std::string& what) const;
};

%pythonappend CoupledResistance::getResistance %{
    val = _units.square_matrix(val)
%}
%pythonappend CoupledResistance::getMobility %{
    val = _units.square_matrix(val)
%}

class CoupledResistance {
public:
    CoupledResistance();
    void setPeriodicBox(const Vec3& a, const Vec3& b, const Vec3& c);
    void setWall(double z0);
    int addBody(const std::vector<Vec3>& blobPositions, const std::vector<double>& blobRadii, const Vec3& origin);
    int getNumBodies() const;
    void setBodyResistance(int body, const ResistanceTensor& own);
    std::vector<double> getResistance() const;
    std::vector<double> getMobility() const;
};

}
