#ifndef RIGID_LANGEVIN_BODY_DYNAMICS_H_
#define RIGID_LANGEVIN_BODY_DYNAMICS_H_

#include "internal/RigidBodyModel.h"
#include "internal/StepCoefficients.h"
#include "openmm/Vec3.h"
#include <cmath>

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
 * Rotate a body about its body axis `axis` by `angle`: Q -> R^T Q, and each body-frame vector
 * v -> R^T v, where R is the right-handed rotation by angle about that axis.
 */
inline void rotateAboutAxis(double q[3][3], int axis, double angle, OpenMM::Vec3* vectors, int numVectors) {
    int b = (axis+1)%3, c = (axis+2)%3;
    double cs = std::cos(angle), sn = std::sin(angle);
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
 * The symmetric DLM splitting of free rotation over a time dt: exact rotations about body axes
 * x(dt/2) y(dt/2) z(dt) y(dt/2) x(dt/2), each by the angle (sub-step)*drive_k/I_k taken from the
 * current, already rotated, drive. `drive` is rotated along, and so are the `carried` vectors.
 * With drive = j this is the time-reversible, symplectic free-rotor map of Dullweber, Leimkuhler
 * and McLachlan; axes that do not rotate are skipped.
 */
inline void dlmRotate(double q[3][3], const BodyType& type, double dt, OpenMM::Vec3& drive, OpenMM::Vec3* carried, int numCarried) {
    static const int axes[5] = {0, 1, 2, 1, 0};
    static const double fractions[5] = {0.5, 0.5, 1.0, 0.5, 0.5};
    OpenMM::Vec3 vectors[3];
    vectors[0] = drive;
    for (int i = 0; i < numCarried; i++)
        vectors[i+1] = carried[i];
    for (int s = 0; s < 5; s++) {
        int axis = axes[s];
        if (!type.rotates(axis))
            continue;
        double angle = fractions[s]*dt*vectors[0][axis]/type.inertia[axis];
        rotateAboutAxis(q, axis, angle, vectors, numCarried+1);
    }
    drive = vectors[0];
    for (int i = 0; i < numCarried; i++)
        carried[i] = vectors[i+1];
}

/** Add dt*force to the momentum and dt*torque (body frame) to the angular momentum. */
inline void kick(BodyState& s, const BodyType& type, const OpenMM::Vec3& force, const OpenMM::Vec3& bodyTorque, double dt) {
    s.velocity += force*(dt/type.mass);
    for (int k = 0; k < 3; k++)
        if (type.rotates(k))
            s.angularMomentum[k] += dt*bodyTorque[k];
}

/** The generalized velocity on the active coordinates. */
inline void generalizedVelocity(const BodyState& s, const BodyType& type, const TypeStepCoefficients& c, double* u) {
    OpenMM::Vec3 vb = toBody(s.rotation, s.velocity);
    for (int i = 0; i < c.dof; i++) {
        int a = c.active[i];
        u[i] = (a < 3 ? vb[a] : s.angularMomentum[a-3]/type.inertia[a-3]);
    }
}

/** y = A x on the active coordinates; diagonal types multiply by the diagonal alone. */
inline void multiply(const Matrix6& a, const TypeStepCoefficients& c, const double* x, double* y) {
    if (c.frictionClass == FrictionClass::Coupled)
        for (int i = 0; i < c.dof; i++) {
            double sum = 0;
            for (int j = 0; j < c.dof; j++)
                sum += a(i, j)*x[j];
            y[i] = sum;
        }
    else
        for (int i = 0; i < c.dof; i++)
            y[i] = a(i, i)*x[i];
}

/**
 * The exact flow of the free body under friction and noise over h (the ExactFlow scheme, between
 * the force kicks). Velocity and displacement of every mode are drawn jointly from their exact
 * Gaussian; the translation is applied in the body frame of the start of the step, and the rotation
 * through the DLM sequence driven by the mean angular momentum of the step, I*theta/h, so that with
 * no friction this is exactly the velocity Verlet drift with DLM rotation.
 */
template <class Random>
void exactFlow(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, double h, Random& random) {
    double u[6], a[6], y[6], displacement[6];
    generalizedVelocity(s, type, c, u);
    multiply(c.toModes, c, u, a);
    for (int i = 0; i < c.dof; i++) {
        const ModeCoefficients& m = c.modes[i];
        double n1 = random.next(), n2 = random.next();
        y[i] = m.drift*a[i]+m.noiseCross*n1+m.noiseDisplacement*n2;
        a[i] = m.decay*a[i]+m.noiseVelocity*n1;
    }
    multiply(c.fromModes, c, a, u);
    multiply(c.fromModes, c, y, displacement);
    OpenMM::Vec3 dx, vb, j, drive;
    for (int i = 0; i < c.dof; i++) {
        int k = c.active[i];
        if (k < 3) {
            dx[k] = displacement[i];
            vb[k] = u[i];
        }
        else {
            j[k-3] = type.inertia[k-3]*u[i];
            drive[k-3] = type.inertia[k-3]*displacement[i]/h;
        }
    }
    s.position += toLab(s.rotation, dx);
    s.velocity = toLab(s.rotation, vb);
    if (type.numRotations > 0) {
        dlmRotate(s.rotation, type, h, drive, &j, 1);
        s.angularMomentum = j;
    }
}

/** The exact Ornstein-Uhlenbeck step of the velocities over h (BAOAB's O). */
template <class Random>
void ornsteinUhlenbeck(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, Random& random) {
    double u[6], a[6];
    generalizedVelocity(s, type, c, u);
    multiply(c.toModes, c, u, a);
    for (int i = 0; i < c.dof; i++)
        a[i] = c.modes[i].decay*a[i]+c.modes[i].noiseVelocity*random.next();
    multiply(c.fromModes, c, a, u);
    OpenMM::Vec3 vb;
    for (int i = 0; i < c.dof; i++) {
        int k = c.active[i];
        if (k < 3)
            vb[k] = u[i];
        else
            s.angularMomentum[k-3] = type.inertia[k-3]*u[i];
    }
    s.velocity = toLab(s.rotation, vb);
}

/** The free drift over dt: translation and DLM rotation (BAOAB's A). */
inline void drift(BodyState& s, const BodyType& type, double dt) {
    s.position += s.velocity*dt;
    if (type.numRotations > 0)
        dlmRotate(s.rotation, type, dt, s.angularMomentum, NULL, 0);
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
template <class Random>
void originalStep(BodyState& s, const BodyType& type, const TypeStepCoefficients& c, const OpenMM::Vec3& force,
                  const OpenMM::Vec3& bodyTorque, double h, Random& random) {
    double uHalf[6], u[6], g[6], noise[6], totalForce[6];
    generalizedVelocity(s, type, c, uHalf);
    OpenMM::Vec3 fb = toBody(s.rotation, force);
    for (int i = 0; i < c.dof; i++) {
        int k = c.active[i];
        g[i] = (k < 3 ? fb[k] : bodyTorque[k-3]);
        noise[i] = random.next();
    }
    for (int i = 0; i < c.dof; i++)
        for (int j = 0; j <= i; j++)
            g[i] += c.randomForce(i, j)*noise[j];
    for (int i = 0; i < c.dof; i++)
        u[i] = uHalf[i];
    for (int iteration = 0; iteration < OriginalSchemeMaxIterations; iteration++) {
        double change = 0, size = 0, next[6];
        for (int i = 0; i < c.dof; i++) {
            double friction = 0;
            for (int j = 0; j < c.dof; j++)
                friction += c.friction(i, j)*u[j];
            next[i] = uHalf[i]+0.5*h*c.inverseMass[i]*(g[i]-friction);
            change = std::max(change, std::abs(next[i]-u[i]));
            size = std::max(size, std::abs(next[i]));
        }
        for (int i = 0; i < c.dof; i++)
            u[i] = next[i];
        if (change <= OriginalSchemeTolerance*size)
            break;
    }
    OpenMM::Vec3 vb, fTotal;
    for (int i = 0; i < c.dof; i++) {
        double friction = 0;
        for (int j = 0; j < c.dof; j++)
            friction += c.friction(i, j)*u[j];
        totalForce[i] = g[i]-friction;
        int k = c.active[i];
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

} // namespace BodyDynamics
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BODY_DYNAMICS_H_*/
