#ifndef RIGID_LANGEVIN_STEP_COEFFICIENTS_H_
#define RIGID_LANGEVIN_STEP_COEFFICIENTS_H_

#include "internal/RigidBodyModel.h"
#include "internal/windowsExportRigidLangevin.h"
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The exact solution over one step h of a scalar Ornstein-Uhlenbeck mode with its displacement,
 *
 *     dw = -lambda w dt + sqrt(2 lambda kT) dB,   dy = w dt,
 *
 * in mass-weighted units (w = sqrt(m) v, y = sqrt(m) x):
 *
 *     w(h) = decay*w(0) + noiseVelocity*n1
 *     y(h) = y(0) + drift*w(0) + noiseCross*n1 + noiseDisplacement*n2
 *
 * with n1, n2 independent standard normal numbers: decay = exp(-lambda h),
 * drift = (1-exp(-lambda h))/lambda, and the noise terms the Cholesky factor of the 2x2 covariance
 * kT [[1-e^2, (1-e)^2/lambda], [(1-e)^2/lambda, (2 lambda h - 3 + 4e - e^2)/lambda^2]].
 * lambda = 0 gives free flight (decay 1, drift h, no noise).
 */
struct ModeCoefficients {
    double lambda, decay, drift, noiseVelocity, noiseCross, noiseDisplacement;
};

/** Compute the coefficients of one mode, accurately for any lambda*h (series below 0.1). */
OPENMM_EXPORT_RIGIDLANGEVIN ModeCoefficients computeModeCoefficients(double lambda, double kT, double h);

/**
 * The splitting schemes the coefficients are computed for (RigidLangevinIntegrator::Scheme, as the
 * model sees it: the model and coefficients depend on plain data, not on the integrator).
 */
enum class SplittingScheme {
    ExactFlow = 0,  // the values of RigidLangevinIntegrator::Scheme (checked where both are seen)
    BAOAB = 1,
    Original = 2,
    Overdamped = 3  // RigidBrownianIntegrator
};

/**
 * The time by which reported velocities are shifted forward (half a kick) to be on-step: zero with
 * friction under ExactFlow and BAOAB, whose stored mid-step velocities are the ones with the exact
 * thermal distribution; half a step for velocity Verlet (no friction) and the Original scheme.
 */
inline double velocityTimeOffset(SplittingScheme scheme, double viscosity, double stepSize) {
    if (scheme == SplittingScheme::Overdamped)
        return 0.0;
    bool onStep = (viscosity == 0 || scheme == SplittingScheme::Original);
    return onStep ? 0.5*stepSize : 0.0;
}

/**
 * Everything a kernel needs to advance the bodies of one type by one step in a given scheme,
 * temperature, viscosity and step size. Generalized coordinates are the active ones of the type
 * (BodyType::getActiveCoordinates(): translation in the body frame, then rotation about the body
 * axes that rotate), BodyType::getNumDegreesOfFreedom() of them; matrices fill their top-left
 * block of that size, in that order (activeCoordinate in RigidBodyModel.h).
 *
 * With W = M^1/2 U (U the generalized velocity, M the mass matrix) and K = M^-1/2 (viscosity Xi)
 * M^-1/2 = S diag(lambda) S^T, the modes are a = S^T W: toModes = S^T M^1/2 and
 * fromModes = M^-1/2 S. For Diagonal and Scalar types S is the identity and the matrices are
 * diagonal.
 */
struct TypeStepCoefficients {
    FrictionClass frictionClass;
    Matrix6 toModes, fromModes;   ///< ExactFlow and BAOAB
    /**
     * ExactFlow: the modes over h/2 if halfSteps (bodies that rotate: the flow is taken as two exact
     * halves to get the mid-step angular velocity that drives the gyroscopic rotation), else over h.
     * BAOAB: over h (decay and noiseVelocity).
     */
    ModeCoefficients modes[6];
    bool halfSteps;
    /**
     * ExactFlow: per generalized coordinate (0-5), c = (2/x)(1-exp(-x/2)) with x = h*K_kk: the
     * fraction of a velocity that still moves the body ballistically over a step. It scales the
     * velocities that drive the free-rotor (gyroscopic) motion: 1 without friction, 2/(gamma h) when
     * friction is stiff and a body no longer turns ballistically within a step.
     */
    double driveFraction[6];
    Matrix6 friction;             ///< Original: viscosity*Xi on the active coordinates
    Matrix6 randomForce;          ///< Original: Cholesky factor of 2 kT viscosity Xi / h
    double inverseMass[6];        ///< Original: M^-1 on the active coordinates
    double stiffness;             ///< (h/2) * largest eigenvalue of M^-1 viscosity Xi
    /**
     * The share of a full kick (h M^-1 times the body's generalized force, a U-vector) that takes
     * the stored velocity (kept between the flow and the next kick, or half a kick behind) to the
     * synchronous one a body-state read-out reports: ExactFlow with friction, fromModes
     * diag(synchronousShare(lambda_k h)) toModes, with which the mean velocity of a body under a
     * constant force is exactly its drift at any step; one half (velocity Verlet's on-step
     * velocity) in the other schemes and without friction.
     */
    Matrix6 synchronousKick;
    /** Overdamped: each body's own mobility (viscosity Xi)^-1 on the active coordinates (body frame), and its Cholesky factor (lower). */
    Matrix6 mobility, mobilityFactor;
};

/**
 * beta(x) = 1/x - 1/(e^x - 1): the share of a kick that, added to the velocity an exact free flow
 * over a step with x = lambda h leaves, makes the exact solution of the flow under a force that is
 * constant over the step (its velocity relaxes to F/(m lambda) while the kicks' impulses decay).
 * 1/2 at x = 0, 1/x as x grows.
 */
OPENMM_EXPORT_RIGIDLANGEVIN double synchronousShare(double x);

/** Compute the step coefficients of every body type of a model. */
OPENMM_EXPORT_RIGIDLANGEVIN std::vector<TypeStepCoefficients> computeStepCoefficients(const RigidBodyModel& model,
        SplittingScheme scheme, double temperature, double viscosity, double stepSize);

/**
 * Check that the Original scheme can run: its fixed-point iteration for the friction of the second
 * half kick only converges while (h/2)*lambda_max < 1. Throws an OpenMMException naming the body
 * and the largest stable step otherwise.
 */
OPENMM_EXPORT_RIGIDLANGEVIN void checkOriginalSchemeStability(const RigidBodyModel& model, const std::vector<TypeStepCoefficients>& coefficients, double stepSize);

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_STEP_COEFFICIENTS_H_*/
