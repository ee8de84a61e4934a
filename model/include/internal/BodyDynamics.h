#ifndef RIGID_LANGEVIN_BODY_DYNAMICS_H_
#define RIGID_LANGEVIN_BODY_DYNAMICS_H_

#include "internal/RigidBodyModel.h"
#include "internal/StepCoefficients.h"
#include "openmm/Vec3.h"
#include <cmath>
#include <type_traits>

namespace RigidLangevinPlugin {

/**
 * The equations of motion of one rigid body, in double precision, as the CPU-side kernels apply
 * them. Conventions: Q (BodyState::rotation) maps lab vectors to body vectors; the body-frame
 * angular momentum j obeys dj/dt = j x omega + torque; a free rotation about body axis k by angle a
 * maps Q -> R_k(a)^T Q and j -> R_k(a)^T j. Generalized velocities U are (Q V, omega) restricted to
 * the type's active coordinates.
 */
namespace BodyDynamics {

/** Q v: a lab vector in the body frame. */
inline OpenMM::Vec3 toBody(const double q[3][3], const OpenMM::Vec3& v) {
    return OpenMM::Vec3(q[0][0]*v[0]+q[0][1]*v[1]+q[0][2]*v[2],
                        q[1][0]*v[0]+q[1][1]*v[1]+q[1][2]*v[2],
                        q[2][0]*v[0]+q[2][1]*v[1]+q[2][2]*v[2]);
}

/** Q^T v: a body vector in the lab frame. */
inline OpenMM::Vec3 toLab(const double q[3][3], const OpenMM::Vec3& v) {
    return OpenMM::Vec3(q[0][0]*v[0]+q[1][0]*v[1]+q[2][0]*v[2],
                        q[0][1]*v[0]+q[1][1]*v[1]+q[2][1]*v[2],
                        q[0][2]*v[0]+q[1][2]*v[1]+q[2][2]*v[2]);
}

/**
 * The sine and cosine of an angle. Trigonometry sits on the serial chain of a body's rotations (each
 * sub-rotation's angle depends on the one before), and the angles a body turns by in a step are
 * small (thermal rotation: ~0.01 rad). Below 0.1 rad the Taylor series are summed to the x^11 and
 * x^10 terms: the first terms left out are below 2e-21 relative, far below rounding. They are
 * summed as polynomials in x^2 by Estrin's scheme (pairs of terms, then powers x^4, x^8 of x^2),
 * whose dependency chain is half as long as Horner's; both round to within an ulp or two of
 * std::sin and std::cos. Larger angles use the library functions.
 */
inline void sineAndCosine(double angle, double& sn, double& cs) {
    double x2 = angle*angle;
    if (x2 < 0.01) {
        double x4 = x2*x2, x8 = x4*x4;
        // sin(x)/x = s0 + s1 x^2 + ... + s5 x^10 and cos(x) = c0 + c1 x^2 + ... + c5 x^10, with sk =
        // (-1)^k/(2k+1)! and ck = (-1)^k/(2k)!.
        double s01 = 1-x2*(1.0/6), s23 = 1.0/120-x2*(1.0/5040), s45 = 1.0/362880-x2*(1.0/39916800);
        double c01 = 1-x2*0.5, c23 = 1.0/24-x2*(1.0/720), c45 = 1.0/40320-x2*(1.0/3628800);
        sn = angle*(s01+(x4*s23+x8*s45));
        cs = c01+(x4*c23+x8*c45);
        return;
    }
    sn = std::sin(angle);
    cs = std::cos(angle);
}

/**
 * Rotate a body about its body axis Axis by `angle`: Q -> R^T Q, and each body-frame vector
 * v -> R^T v, where R is the right-handed rotation by angle about that axis. A null q turns the
 * vectors alone. The axis is a template argument: the DLM chain names its five axes in the code,
 * and the other two axes' indices are then constants (computing them at run time was 4% of the
 * CPU step's instructions).
 */
template <int Axis>
inline void rotateAboutAxis(double q[3][3], double angle, OpenMM::Vec3* vectors, int numVectors) {
    constexpr int b = (Axis+1)%3, c = (Axis+2)%3;
    double cs, sn;
    sineAndCosine(angle, sn, cs);
    if (q != nullptr)
        for (int k = 0; k < 3; k++) {
            double qb = q[b][k], qc = q[c][k];
            q[b][k] = cs*qb+sn*qc;
            q[c][k] = cs*qc-sn*qb;
        }
    for (int i = 0; i < numVectors; i++) {
        double vb = vectors[i][b], vc = vectors[i][c];
        vectors[i][b] = cs*vb+sn*vc;
        vectors[i][c] = cs*vc-sn*vb;
    }
}

/**
 * Rotate a body by the rotation vector phi (body frame): Q -> R^T Q and v -> R^T v for each
 * body-frame vector, with R = exp(skew(phi)) by Rodrigues' formula. A null q turns the vectors alone.
 */
inline void rotateByVector(double q[3][3], const OpenMM::Vec3& phi, OpenMM::Vec3* vectors, int numVectors) {
    double angle = std::sqrt(phi.dot(phi));
    if (angle == 0)
        return;
    OpenMM::Vec3 n = phi/angle;
    double cs, sn;
    sineAndCosine(angle, sn, cs);
    // R^T v = cos(a) v - sin(a) n x v + (1-cos(a)) (n.v) n
    auto apply = [&](const OpenMM::Vec3& v) {
        return v*cs-n.cross(v)*sn+n*((1-cs)*n.dot(v));
    };
    if (q != nullptr)
        for (int k = 0; k < 3; k++) {
            OpenMM::Vec3 column = apply(OpenMM::Vec3(q[0][k], q[1][k], q[2][k]));
            for (int i = 0; i < 3; i++)
                q[i][k] = column[i];
        }
    for (int i = 0; i < numVectors; i++)
        vectors[i] = apply(vectors[i]);
}

/**
 * A linear body has no angular momentum about its axis (body axis 0); rotations of the frame tilt
 * carried vectors onto it, and that component is removed.
 */
inline void removeAxialComponent(const BodyType& type, OpenMM::Vec3& v) {
    for (int k = 0; k < 3; k++)
        if (!type.rotates(k))
            v[k] = 0;
}

/**
 * The DLM splitting's five sub-rotations (freeRotate), about the body axes x, y, z, y, x; step(Axis,
 * s) is called for each with the axis and the sub-rotation's index.
 */
template <class Step>
inline void forEachDlmRotation(Step&& step) {
    step(std::integral_constant<int, 0>(), 0);
    step(std::integral_constant<int, 1>(), 1);
    step(std::integral_constant<int, 2>(), 2);
    step(std::integral_constant<int, 1>(), 3);
    step(std::integral_constant<int, 0>(), 4);
}

/**
 * The angle per unit of drive of each DLM sub-rotation over dt, computed before the chain of
 * sub-rotations (each waits for the one before) so that no division sits on it.
 */
inline void dlmRates(const BodyType& type, double dt, double rate[5]) {
    const double half = 0.5*dt;
    rate[0] = rate[4] = half/type.inertia[0];
    rate[1] = rate[3] = half/type.inertia[1];
    rate[2] = dt/type.inertia[2];
}

/**
 * The free rotation of a body over a time dt, driven by the body-frame angular momentum `drive`
 * (rotated along, like the `carried` vectors). For a body with three moments this is the symmetric
 * DLM splitting of Dullweber, Leimkuhler and McLachlan: exact rotations about the body axes
 * x(dt/2) y(dt/2) z(dt) y(dt/2) x(dt/2), each by the angle (sub-step)*drive_k/I_k of the current
 * drive; time-reversible and symplectic. A linear body (equal moments about axes 1 and 2) rotates
 * exactly, about its angular velocity. A null q turns the vectors alone.
 */
inline void freeRotate(double q[3][3], const BodyType& type, double dt, OpenMM::Vec3& drive, OpenMM::Vec3* carried, int numCarried) {
    OpenMM::Vec3 vectors[3];
    vectors[0] = drive;
    for (int i = 0; i < numCarried; i++)
        vectors[i+1] = carried[i];
    if (type.numRotations == 2) {
        OpenMM::Vec3 phi(0, dt*drive[1]/type.inertia[1], dt*drive[2]/type.inertia[2]);
        rotateByVector(q, phi, vectors, numCarried+1);
        for (int i = 0; i <= numCarried; i++)
            removeAxialComponent(type, vectors[i]);
    }
    else {
        double rate[5];
        dlmRates(type, dt, rate);
        forEachDlmRotation([&] (auto axis, int s) {
            rotateAboutAxis<axis.value>(q, rate[s]*vectors[0][axis.value], vectors, numCarried+1);
        });
    }
    drive = vectors[0];
    for (int i = 0; i < numCarried; i++)
        carried[i] = vectors[i+1];
}

/**
 * Two free rotations of a body with three moments over dt, with the results of
 * freeRotate(q, type, dt, frameDrive, NULL, 0) and of freeRotate(nullptr, type, dt, vectors[0],
 * vectors+1, numVectors-1) bit for bit (vectors[0] is the second rotation's drive), their
 * sub-rotations interleaved. Each sub-rotation waits for the one before (its angle comes from the
 * drive that one turned), so one chain alone leaves the processor waiting; two independent chains
 * side by side fill those waits.
 */
inline void freeRotateFrameAndVectors(double q[3][3], const BodyType& type, double dt, OpenMM::Vec3& frameDrive, OpenMM::Vec3* vectors,
                                      int numVectors) {
    double rate[5];
    dlmRates(type, dt, rate);
    forEachDlmRotation([&] (auto axis, int s) {
        rotateAboutAxis<axis.value>(q, rate[s]*frameDrive[axis.value], &frameDrive, 1);
        rotateAboutAxis<axis.value>(nullptr, rate[s]*vectors[0][axis.value], vectors, numVectors);
    });
}

/**
 * The force on a body of this type whose particles are these (System indices), and its torque in
 * the body frame, from every particle's force: a virtual site's entry is skipped, OpenMM having
 * already handed its force to its parents (all in this body).
 */
inline void gatherForce(const BodyType& type, const BodyParticles& particles, const BodyState& s, const std::vector<OpenMM::Vec3>& forces,
                        OpenMM::Vec3& force, OpenMM::Vec3& torque) {
    force = OpenMM::Vec3();
    torque = OpenMM::Vec3();
    for (int i = 0; i < particles.size(); i++) {
        if (type.isVirtualSite[i])
            continue;
        const OpenMM::Vec3& fi = forces[particles[i]];
        force += fi;
        if (type.numRotations > 0)
            torque += type.coords[i].cross(toBody(s.rotation, fi));
    }
}

/** Add dt*force to the momentum and dt*torque (body frame) to the angular momentum. */
inline void kick(BodyState& s, const BodyType& type, const OpenMM::Vec3& force, const OpenMM::Vec3& bodyTorque, double dt) {
    s.velocity += force*(dt/type.mass);
    for (int k = 0; k < 3; k++)
        if (type.rotates(k))
            s.angularMomentum[k] += dt*bodyTorque[k];
}

/**
 * Move a stored body state's velocities to the synchronous ones (TypeStepCoefficients::
 * synchronousKick) with the body's force (lab frame) and torque (body frame) at its position.
 */
inline void synchronousVelocity(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, const OpenMM::Vec3& force,
                                const OpenMM::Vec3& bodyTorque, double h) {
    const std::vector<int> active = type.getActiveCoordinates();
    const int dof = active.size();
    Vector6 kick = Vector6::Zero();
    OpenMM::Vec3 bodyForce = toBody(s.rotation, force);
    for (int i = 0; i < dof; i++)
        kick[i] = (active[i] < 3 ? h*bodyForce[active[i]]/type.mass : h*bodyTorque[active[i]-3]/type.inertia[active[i]-3]);
    Vector6 shift = c.synchronousKick*kick;
    OpenMM::Vec3 translation;
    for (int i = 0; i < dof; i++) {
        if (active[i] < 3)
            translation[active[i]] = shift[i];
        else
            s.angularMomentum[active[i]-3] += type.inertia[active[i]-3]*shift[i];
    }
    s.velocity += toLab(s.rotation, translation);
}

/**
 * Call f(std::integral_constant<int, R>()) with R the body's number of rotating axes. The flows below
 * take R as a template argument, so that their loops over the active coordinates (activeCoordinate
 * in RigidBodyModel.h) unroll and no branch on a coordinate's kind is left.
 */
template <class F>
inline void withRotations(const BodyType& type, F&& f) {
    if (type.numRotations == 0)
        f(std::integral_constant<int, 0>());
    else if (type.numRotations == 2)
        f(std::integral_constant<int, 2>());
    else
        f(std::integral_constant<int, 3>());
}

/** The generalized velocity on the active coordinates. */
template <int Rotations>
inline void generalizedVelocity(const BodyState& s, const BodyType& type, double* u) {
    OpenMM::Vec3 vb = toBody(s.rotation, s.velocity);
    for (int i = 0; i < 3+Rotations; i++) {
        int k = activeCoordinate(Rotations, i);
        u[i] = (k < 3 ? vb[k] : s.angularMomentum[k-3]/type.inertia[k-3]);
    }
}

/** y = A x on the Dof active coordinates; diagonal types multiply by the diagonal alone. */
template <int Dof>
inline void multiply(const Matrix6& a, FrictionClass frictionClass, const double* x, double* y) {
    if (frictionClass == FrictionClass::Coupled)
        for (int i = 0; i < Dof; i++) {
            double sum = 0;
            for (int j = 0; j < Dof; j++)
                sum += a(i, j)*x[j];
            y[i] = sum;
        }
    else
        for (int i = 0; i < Dof; i++)
            y[i] = a(i, i)*x[i];
}

/**
 * The exact flow of the free body under friction and noise over h (the ExactFlow scheme, between
 * the force kicks). The linear Langevin equation of the body-frame velocities U is solved exactly:
 * end velocity and displacement X (the integral of U) of every mode are drawn jointly from their
 * exact Gaussian. Bodies that rotate take it as two exact halves, so that the mid-step velocity,
 * exactly Maxwellian, is known too.
 *
 * What the linear flow lacks is second order in the step and comes from the frame turning:
 *  - Rotation: theta (the rotational part of X) plus the free rotor's gyroscopic motion. A fraction
 *    c of the mid-step angular velocity w (TypeStepCoefficients::driveFraction) drives a free
 *    rotation over h; the rest of theta is applied half before, half after it:
 *    exp((theta - h c w)/2) freeRotate(I c w, h) exp((theta - h c w)/2). Driving it with an
 *    equal-time velocity keeps its mean zero, as the true gyroscopic term's is.
 *  - Translation: friction and noise act in the turning body frame, which adds (theta x X)/2 in the
 *    mean (the Stratonovich drift that makes the centre of diffusion, not the centre of mass, set
 *    the long-time diffusion). Without friction the body frame does not matter, so the same
 *    product of mid-step velocities, (h c w) x (h c v)/2, is taken off: zero in the mean, all of it
 *    at zero viscosity.
 *  - Angular momentum and velocity: the end values (body frame) turn into the new body frame by the
 *    free-rotor motion of the end angular momentum, scaled by c, alone. Turning the velocity by the
 *    whole rotation, as a lab-frame velocity kept through the step would be, is wrong with friction:
 *    the rest of the rotation is the diffusive part of theta, correlated with the end velocity
 *    wherever the centre of mass is not the centre of diffusion, so it would kick the body-frame
 *    velocity by a nonzero mean -<theta x v> every step (the true turning term, -omega x v, has zero
 *    mean). That mean kick gave the centre of diffusion a spurious drift in the body frame and the
 *    long-time translational diffusion a bias (+2% to +6% at lambda_max h from 3 to 100 for a
 *    tensor origin 0.18 nm off the centre of mass). The end angular velocity is uncorrelated with the
 *    end velocity, so this turn has zero mean; as friction vanishes it becomes the body's own DLM
 *    rotation, and the lab-frame velocity is kept exactly.
 * Without friction this is exactly velocity Verlet with DLM rotation; with stiff friction c ->
 * 2/(gamma h) and it tends to Brownian dynamics with the right drift.
 */
template <int Rotations, class Random>
void exactFlowOf(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, double h, Random& random) {
    constexpr int Dof = 3+Rotations;
    double u[6], a[6], mid[6], y[6], displacement[6];
    generalizedVelocity<Rotations>(s, type, u);
    multiply<Dof>(c.toModes, c.frictionClass, u, a);
    for (int i = 0; i < Dof; i++) {
        const ModeCoefficients& m = c.modes[i];
        double n1 = random.next(), n2 = random.next();
        y[i] = m.drift*a[i]+m.noiseCross*n1+m.noiseDisplacement*n2;
        a[i] = m.decay*a[i]+m.noiseVelocity*n1;
        if (c.halfSteps) {
            mid[i] = a[i];
            double n3 = random.next(), n4 = random.next();
            y[i] += m.drift*a[i]+m.noiseCross*n3+m.noiseDisplacement*n4;
            a[i] = m.decay*a[i]+m.noiseVelocity*n3;
        }
    }
    multiply<Dof>(c.fromModes, c.frictionClass, a, u);
    multiply<Dof>(c.fromModes, c.frictionClass, y, displacement);
    OpenMM::Vec3 dx, vb, j, theta;
    for (int i = 0; i < Dof; i++) {
        int k = activeCoordinate(Rotations, i);
        if (k < 3) {
            dx[k] = displacement[i];
            vb[k] = u[i];
        }
        else {
            j[k-3] = type.inertia[k-3]*u[i];
            theta[k-3] = displacement[i];
        }
    }
    if (Rotations == 0) {
        s.velocity = toLab(s.rotation, vb);
        s.position += toLab(s.rotation, dx);
        return;
    }
    double midVelocity[6];
    multiply<Dof>(c.fromModes, c.frictionClass, mid, midVelocity);
    OpenMM::Vec3 vMid, wMid;  // mid-step velocities, scaled by their drive fractions
    for (int i = 0; i < Dof; i++) {
        int k = activeCoordinate(Rotations, i);
        if (k < 3)
            vMid[k] = c.driveFraction[k]*midVelocity[i];
        else
            wMid[k-3] = c.driveFraction[k]*midVelocity[i];
    }
    s.position += toLab(s.rotation, dx+(theta.cross(dx)-wMid.cross(vMid)*(h*h))*0.5);
    OpenMM::Vec3 drive, rest;
    for (int k = 0; k < 3; k++) {
        drive[k] = type.inertia[k]*wMid[k];
        rest[k] = 0.5*(theta[k]-h*wMid[k]);
    }
    OpenMM::Vec3 jDrive;
    for (int k = 0; k < 3; k++)
        jDrive[k] = c.driveFraction[3+k]*j[k];
    // The frame turns; the vectors alone turn too, into the body's new frame.
    rotateByVector(s.rotation, rest, &drive, 1);
    if (Rotations == 2) {
        freeRotate(s.rotation, type, h, drive, NULL, 0);
        // A linear body's velocity keeps its axial component: it turns by the same exact rotation.
        OpenMM::Vec3 phi(0, h*jDrive[1]/type.inertia[1], h*jDrive[2]/type.inertia[2]);
        rotateByVector(nullptr, phi, &vb, 1);
        freeRotate(nullptr, type, h, jDrive, &j, 1);
    }
    else {
        OpenMM::Vec3 turned[3] = {jDrive, j, vb};
        freeRotateFrameAndVectors(s.rotation, type, h, drive, turned, 3);
        j = turned[1];
        vb = turned[2];
    }
    rotateByVector(s.rotation, rest, NULL, 0);
    s.velocity = toLab(s.rotation, vb);
    s.angularMomentum = j;
    removeAxialComponent(type, s.angularMomentum);
}

template <class Random>
void exactFlow(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, double h, Random& random) {
    withRotations(type, [&] (auto rotations) {
        exactFlowOf<decltype(rotations)::value>(s, type, c, h, random);
    });
}

/** The exact Ornstein-Uhlenbeck step of the velocities over h (BAOAB's O). */
template <int Rotations, class Random>
void ornsteinUhlenbeckOf(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, Random& random) {
    constexpr int Dof = 3+Rotations;
    double u[6], a[6];
    generalizedVelocity<Rotations>(s, type, u);
    multiply<Dof>(c.toModes, c.frictionClass, u, a);
    for (int i = 0; i < Dof; i++)
        a[i] = c.modes[i].decay*a[i]+c.modes[i].noiseVelocity*random.next();
    multiply<Dof>(c.fromModes, c.frictionClass, a, u);
    OpenMM::Vec3 vb;
    for (int i = 0; i < Dof; i++) {
        int k = activeCoordinate(Rotations, i);
        if (k < 3)
            vb[k] = u[i];
        else
            s.angularMomentum[k-3] = type.inertia[k-3]*u[i];
    }
    s.velocity = toLab(s.rotation, vb);
}

template <class Random>
void ornsteinUhlenbeck(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, Random& random) {
    withRotations(type, [&] (auto rotations) {
        ornsteinUhlenbeckOf<decltype(rotations)::value>(s, type, c, random);
    });
}

/** The free drift over dt: translation and free rotation (BAOAB's A, velocity Verlet's drift). */
inline void drift(BodyState& s, const BodyType& type, double dt) {
    s.position += s.velocity*dt;
    if (type.numRotations > 0)
        freeRotate(s.rotation, type, dt, s.angularMomentum, NULL, 0);
}

/** Iterations and tolerance of the Original scheme's fixed-point iteration, as in OpenMD. */
const int OriginalSchemeMaxIterations = 6;
const double OriginalSchemeTolerance = 1e-6;

/**
 * One step of the source's scheme. With the systematic force and torque at the current positions
 * it first finishes the previous step (moveB: the velocity-dependent friction of the second half
 * kick by fixed-point iteration, with a fresh random force of covariance 2 kT viscosity Xi/h), then
 * starts the next (moveA: half kick with the total force, drift, DLM rotation).
 */
template <int Rotations, class Random>
void originalStepOf(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, const OpenMM::Vec3& force,
                    const OpenMM::Vec3& bodyTorque, double h, Random& random) {
    constexpr int Dof = 3+Rotations;
    double uHalf[6], u[6], g[6], noise[6], totalForce[6];
    generalizedVelocity<Rotations>(s, type, uHalf);
    OpenMM::Vec3 fb = toBody(s.rotation, force);
    for (int i = 0; i < Dof; i++) {
        int k = activeCoordinate(Rotations, i);
        g[i] = (k < 3 ? fb[k] : bodyTorque[k-3]);
        noise[i] = random.next();
    }
    for (int i = 0; i < Dof; i++)
        for (int j = 0; j <= i; j++)
            g[i] += c.randomForce(i, j)*noise[j];
    for (int i = 0; i < Dof; i++)
        u[i] = uHalf[i];
    for (int iteration = 0; iteration < OriginalSchemeMaxIterations; iteration++) {
        double change = 0, size = 0, next[6];
        for (int i = 0; i < Dof; i++) {
            double friction = 0;
            for (int j = 0; j < Dof; j++)
                friction += c.friction(i, j)*u[j];
            next[i] = uHalf[i]+0.5*h*c.inverseMass[i]*(g[i]-friction);
            change = std::max(change, std::abs(next[i]-u[i]));
            size = std::max(size, std::abs(next[i]));
        }
        for (int i = 0; i < Dof; i++)
            u[i] = next[i];
        if (change <= OriginalSchemeTolerance*size)
            break;
    }
    OpenMM::Vec3 vb, fTotal;
    for (int i = 0; i < Dof; i++) {
        double friction = 0;
        for (int j = 0; j < Dof; j++)
            friction += c.friction(i, j)*u[j];
        totalForce[i] = g[i]-friction;
        int k = activeCoordinate(Rotations, i);
        if (k < 3) {
            vb[k] = u[i];
            fTotal[k] = totalForce[i];
        }
        else
            s.angularMomentum[k-3] = type.inertia[k-3]*u[i]+0.5*h*totalForce[i];
    }
    s.velocity = toLab(s.rotation, vb+fTotal*(0.5*h/type.mass));
    drift(s, type, h);
}

template <class Random>
void originalStep(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, const OpenMM::Vec3& force,
                  const OpenMM::Vec3& bodyTorque, double h, Random& random) {
    withRotations(type, [&] (auto rotations) {
        originalStepOf<decltype(rotations)::value>(s, type, c, force, bodyTorque, h, random);
    });
}

} // namespace BodyDynamics
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BODY_DYNAMICS_H_*/
