#ifndef RIGID_LANGEVIN_RIGID_BODY_MODEL_H_
#define RIGID_LANGEVIN_RIGID_BODY_MODEL_H_

#include "internal/BodyParticleLists.h"
#include "internal/RigidBodyDescription.h"
#include "internal/windowsExportRigidLangevin.h"
#include "openmm/System.h"
#include "openmm/serialization/SerializationNode.h"
#include "openmm/Vec3.h"
#include <Eigen/Core>
#include <iosfwd>
#include <map>
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

class ExactBodyShapes;

typedef Eigen::Matrix<double, 6, 6> Matrix6;
typedef Eigen::Matrix<double, 6, 1> Vector6;

/**
 * How a body type's friction couples its degrees of freedom, in its principal-axes frame at the
 * centre of mass. Kernels use the cheapest exact update a class allows.
 */
enum class FrictionClass {
    Scalar = 0,   ///< translation only, isotropic (free particles, single-particle bodies)
    Diagonal = 1, ///< no coupling between the degrees of freedom
    Coupled = 2   ///< a general symmetric 6x6 (or 5x5, 3x3) problem
};

/**
 * The generalized coordinate (0-2 translation, 3-5 rotation about body axes 0-2) of active
 * coordinate i of a body with numRotations rotating axes (0, 2 or 3): the three translations, then
 * rotation about the last numRotations body axes (BodyType::rotates). The step coefficients are laid
 * out in this order, and the flows (BodyDynamics.h) walk it with numRotations a template argument,
 * so that their loops unroll. The common kernels (rigidBodyStep.cc) follow the same rule.
 */
constexpr int activeCoordinate(int numRotations, int i) {
    return (i < 3 ? i : i+3-numRotations);
}

/**
 * The shape, mass properties and friction shared by all bodies of one type. Coordinates are in the
 * body frame: origin at the centre of mass, axes along the principal axes of inertia with the
 * moments in ascending order. A linear body rotates about axes 1 and 2 only; a body whose mass is
 * all at one point does not rotate.
 */
struct BodyType {
    std::vector<double> masses;          ///< per particle, in the body's particle order
    std::vector<double> radii;           ///< hydrodynamic radius per particle, 0 for none
    std::vector<OpenMM::Vec3> coords;    ///< body-frame coordinates per particle
    /**
     * 1 for a virtual site, 0 otherwise. OpenMM hands a site's force to its parent particles (all
     * in this body) before the integrator sees it, so a site's own force entry must not count again.
     */
    std::vector<int> isVirtualSite;
    double diameter;                     ///< the largest distance between two of its particles (from coords)
    double mass;                         ///< total mass
    OpenMM::Vec3 inertia;                ///< principal moments, ascending; 0 for axes that do not rotate
    int numRotations;                    ///< 0, 2 (linear) or 3
    bool explicitResistance;             ///< true if the friction came from setBodyResistance()
    Matrix6 resistance;                  ///< per unit viscosity, body frame, about the centre of mass
    FrictionClass frictionClass;
    int getNumDegreesOfFreedom() const {
        return 3+numRotations;
    }
    /** Whether rotation about body axis 0, 1 or 2 is a degree of freedom. */
    bool rotates(int axis) const {
        return axis >= 3-numRotations;
    }
    /** The generalized coordinates (0-2 translation, 3-5 rotation about the body axes) that move, in order (activeCoordinate). */
    std::vector<int> getActiveCoordinates() const;
};

/**
 * The dynamical state of one body: centre of mass (never wrapped into the periodic box, so bodies
 * stay whole), lab-frame velocity, body-frame angular momentum and orientation.
 */
struct BodyState {
    OpenMM::Vec3 position;
    OpenMM::Vec3 velocity;
    OpenMM::Vec3 angularMomentum;
    double rotation[3][3]; ///< Q, lab to body: its rows are the body axes in the lab frame
};

/**
 * Body types and states as a State or a checkpoint carries them: read and checked against the
 * System, not yet applied (RigidBodyModel::restoreStates()).
 */
struct SavedBodies {
    std::vector<BodyType> types;
    std::vector<int> bodyType;   ///< per body, an index into types
    std::vector<BodyState> states;
};

/**
 * The rigid bodies of a System as the integrator moves them: the bodies the user defined followed
 * by one single-particle body per free particle with mass, grouped into types that share shape,
 * masses, radii and friction. This is the API layer's precomputation shared by every platform:
 * kernels get body types and states from here and only apply the equations of motion.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidBodyModel {
public:
    /** Positions that deviate more than this (nm) from a rigid placement of a body are an error. */
    static constexpr double GeometryTolerance = 1e-3;
    /**
     * Check the bodies described against the System and resolve hydrodynamic radii. Throws
     * OpenMMException for bad input (indices, overlaps, massless bodies, constraints that link
     * different bodies, missing radii).
     */
    RigidBodyModel(const OpenMM::System& system, const RigidBodyDescription& description);
    ~RigidBodyModel();
    /** The integrator's class name (RigidLangevinIntegrator or RigidBrownianIntegrator), which begins every error message. */
    const std::string& getIntegratorName() const {
        return integratorName;
    }
    /** The number of bodies moved, free particles included. */
    int getNumBodies() const {
        return bodyParticles.size();
    }
    /** The number of bodies defined with addRigidBody(); they come first. */
    int getNumUserBodies() const {
        return numUserBodies;
    }
    BodyParticles getBodyParticles(int body) const {
        return bodyParticles[body];
    }
    int getNumTypes() const {
        return types.size();
    }
    const BodyType& getType(int type) const {
        return types[type];
    }
    int getBodyType(int body) const {
        return bodyType[body];
    }
    /**
     * Whether some virtual site rides on no body. A site in a body is placed with it, as its
     * parents are (they must be in the same body); only sites outside bodies need OpenMM to place
     * them from their parents after a step.
     */
    bool hasSitesOutsideBodies() const {
        return sitesOutsideBodies;
    }
    /**
     * Fit body states to particle positions and velocities. The first call defines the body types
     * from these positions, made exact first where the System's constraints or virtual sites fix
     * them (ExactBodyShapes), and throws if a body is not whole in them (two of its particles more
     * than half a periodic box apart); later calls fit each body to its type, taking particles at
     * their nearest images (a body wrapped into the box comes back whole), and throw if the
     * positions deform it. Velocities are projected onto rigid motion (momentum and angular
     * momentum kept).
     *
     * @param positions   particle positions
     * @param velocities  particle velocities
     * @param box         the periodic box vectors, or NULL without periodic boundary conditions
     */
    std::vector<BodyState> fitStates(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities,
                                     const OpenMM::Vec3* box);
    /** Write the positions and velocities of every body's particles from body states. */
    void placeParticles(const std::vector<BodyState>& states, std::vector<OpenMM::Vec3>& positions, std::vector<OpenMM::Vec3>& velocities) const;
    /**
     * How placeBodyParticles() writes. An ordinary store reads the cache line it writes first
     * (write-allocate), so a step over arrays larger than the cache moves each particle's position
     * and velocity twice; a non-temporal (streaming) store fills whole lines without reading them and
     * leaves them out of the cache, which only pays once the arrays do not fit in it.
     */
    enum class ParticleStores {
        Cached,    ///< ordinary stores
        Streaming  ///< non-temporal stores on x86-64 (ordinary elsewhere); fence before other threads read them
    };
    /** Write the positions and velocities of one body's particles from its state. */
    void placeBodyParticles(int body, const BodyState& state, std::vector<OpenMM::Vec3>& positions, std::vector<OpenMM::Vec3>& velocities,
                            ParticleStores stores = ParticleStores::Cached) const;
    /**
     * The stores a host step should place particles with: Streaming when what it touches (body
     * states, particle positions, velocities, forces and indices) exceeds cacheBytes, the size of
     * the last-level cache, so that the lines it writes are gone from the cache before the next
     * force evaluation reads them, and the bodies' particles lie in memory in body order (at most
     * one particle in 16 not right after the one written before it), so that streaming stores fill
     * whole lines; Cached otherwise.
     */
    ParticleStores chooseParticleStores(long long cacheBytes) const;
    /**
     * The hydrodynamic blobs of a body type in its frame (nm): those given with setBodyBlobs() to its
     * bodies, or else its particles with a radius. Throws an OpenMMException naming a body whose
     * blobs it cannot carry (off the point of a body that does not rotate, off the axis of a linear
     * one) or that has none.
     */
    void getTypeBlobs(int type, std::vector<OpenMM::Vec3>& coords, std::vector<double>& radii) const;
    /** The name of a body in messages: "rigid body 3", or "free particle 40" for a particle in no body. */
    std::string getBodyName(int body) const;
    /** The first body of a type. */
    int getFirstBodyOfType(int type) const;
    /** Total degrees of freedom, translational ones (3 per body) and rotational ones. */
    int getNumDegreesOfFreedom() const;
    int getNumTranslationalDegreesOfFreedom() const {
        return 3*getNumBodies();
    }
    int getNumRotationalDegreesOfFreedom() const;
    /** The total mass of all bodies. */
    double getTotalMass() const;
    /** Write the body types and their assignment, exactly, for a checkpoint. */
    void writeTypes(std::ostream& stream) const;
    /**
     * Write the body types and their assignment into a State's integrator parameters. A body
     * state (rotation, body-frame angular momentum) means something only in its type's frame, and
     * a Context that builds its types from other positions may choose other principal axes.
     */
    void writeTypes(OpenMM::SerializationNode& node) const;
    /**
     * Read body types written by writeTypes() into saved (its types and bodyType); throws where they
     * are corrupt. Nothing in the model changes: see restoreStates().
     */
    void readTypes(std::istream& stream, SavedBodies& saved) const;
    void readTypes(const OpenMM::SerializationNode& node, SavedBodies& saved) const;
    /**
     * Throw, naming the body, where saved types or states (read by readTypes(), the states by the
     * caller) are corrupt: values out of range, not finite, rotations not orthonormal.
     */
    void checkSavedTypes(const SavedBodies& saved, const std::string& source) const;
    /**
     * The body states saved with another model's types, expressed in this model's: a State or a
     * checkpoint carries where the bodies are and how they move, while this model (built from the
     * integrator the user made) keeps its own friction, radii and blobs. Each saved state is turned
     * into this model's frame of its body (the rotation that takes the saved type's shape onto this
     * type's), or the type takes the saved frame (adoptSavedFrames()), so that the run continues as
     * it would have.
     *
     * @param saved      the saved types, their assignment and the states (checked: checkSavedTypes())
     * @param positions  the particle positions restored with them (the State's or the checkpoint's)
     * @param box        the periodic box vectors, or NULL
     * @param[out] states        the restored states
     * @param[out] typesChanged  whether a body type took the saved frame: its frame, coordinates,
     *                           moments and friction matrix changed (step coefficients, blobs and a
     *                           kernel's copies of the types must be made again)
     * @return false where the saved states do not describe this System's bodies: other bodies or
     *         masses (Context::reinitialize(true) after setParticleMass()), other shapes, or particles
     *         that, placed from the restored states, would not be at the positions given (within
     *         GeometryTolerance; each at its nearest periodic image where box is not NULL), as when
     *         bodies or their particles are listed in another order than where they were saved. The
     *         caller then fits the bodies to the restored particles instead (fitStates()).
     */
    bool restoreStates(const SavedBodies& saved, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box,
                       std::vector<BodyState>& states, bool& typesChanged);
    /** Forget the body types, so that the next fitStates() builds them again from the positions it is given. */
    void clearTypes();
private:
    /** Whether saved types describe this System's bodies: their number, particles and masses. */
    bool savedBodiesMatch(const SavedBodies& saved) const;
    /** Whether particles placed from states are at positions (within GeometryTolerance). */
    bool placedAt(const std::vector<BodyState>& states, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box) const;
    int findOrCreateType(int body, const std::vector<OpenMM::Vec3>& offsets, double rotation[3][3]);
    bool matchType(int type, const std::vector<OpenMM::Vec3>& offsets, double rotation[3][3], double& deviation, int& worst) const;
    int createType(int body, const std::vector<OpenMM::Vec3>& offsets, double rotation[3][3]);
    /**
     * Set a type's friction class from its resistance (zeroing off-diagonal round-off of a diagonal
     * one); throws, naming the body, if it is not positive definite in the motions the body makes.
     */
    void classifyFriction(BodyType& type, const std::string& name) const;
    /**
     * The rotation P from each saved type's frame to this model's frame of the same shape (b_here =
     * P b_saved), for every pair of saved and model types some body has; false if a pair's shapes
     * differ by more than GeometryTolerance. The identity exactly where the coordinates are equal.
     */
    bool fitSavedFrames(const SavedBodies& saved, std::map<std::pair<int, int>, Eigen::Matrix3d>& frameChange) const;
    /**
     * Turn every type whose bodies were all saved with one type into that type's frame (its
     * coordinates and moments as saved; its friction, this model's, rotated into it), and give
     * those bodies their saved states as they are: a run continues exactly where the frame of a
     * body with equal moments (any axes are principal) was chosen otherwise. Returns whether a
     * type changed.
     */
    bool adoptSavedFrames(const SavedBodies& saved, std::vector<BodyState>& states);
    /** The explicit blobs of a body in the frame with rotation (lab to frame) where its particles' offsets from the centre of mass are offsets. */
    /** The rotation from the frame of positions given with a body's tensor or blobs (reference, with
     *  their centre of mass) to its offsets now; refused, naming given and what it was placedFor,
     *  where they are not the body's shape. */
    Eigen::Matrix3d fitGivenReference(int body, const std::vector<OpenMM::Vec3>& reference, const std::vector<OpenMM::Vec3>& offsets,
                                      const std::string& given, const std::string& placedFor, OpenMM::Vec3& referenceCentre) const;
    void explicitBodyFrameBlobs(int body, const std::vector<OpenMM::Vec3>& offsets, const Eigen::Matrix3d& rotation,
                                std::vector<OpenMM::Vec3>& coords) const;
    Matrix6 bodyFrameResistance(int body, const std::vector<OpenMM::Vec3>& offsets, const double rotation[3][3]) const;
    std::vector<OpenMM::Vec3> unwrappedOffsets(int body, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, OpenMM::Vec3& centre) const;
    /** Throw if, in the positions that define the shapes, any body's particles lie more than half a box apart. */
    void checkBodiesWhole(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box) const;
    int numUserBodies;
    BodyParticleLists bodyParticles;
    std::vector<int> particleBody;
    std::vector<double> particleMass, particleRadius;
    std::vector<int> particleIsVirtualSite;
    bool sitesOutsideBodies;
    std::unique_ptr<ExactBodyShapes> exactShapes;
    std::string integratorName;
    std::vector<std::vector<double> > explicitTensor;  // per user body, empty if none
    std::vector<OpenMM::Vec3> explicitOrigin;
    std::vector<std::vector<OpenMM::Vec3> > explicitReference;  // the positions each explicit tensor belongs to
    std::vector<RigidBodyDescription::Body> explicitBlobs;  // per user body: blobs given with setBodyBlobs(), or none
    std::vector<BodyType> types;
    std::vector<int> bodyType;
    std::multimap<std::vector<double>, int> typesBySignature;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_RIGID_BODY_MODEL_H_*/
