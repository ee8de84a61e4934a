#include "internal/StepCoefficients.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

/**
 * (2x - 3 + 4 e^-x - e^-2x)/x^2 without cancellation: the series
 * sum_{n>=3} (-1)^n (4 - 2^n) x^(n-2)/n! below x = 0.5, the closed form above.
 */
double displacementVarianceFactor(double x) {
    if (x >= 0.5)
        return (2*x-3+4*std::exp(-x)-std::exp(-2*x))/(x*x);
    double sum = 0, power = x, factorial = 6, twoPower = 8;
    for (int n = 3; n < 40; n++) {
        double term = (4-twoPower)*power/factorial;
        sum += (n%2 == 0 ? term : -term);
        power *= x;
        factorial *= n+1;
        twoPower *= 2;
    }
    return sum;
}

} // namespace

ModeCoefficients RigidLangevinPlugin::computeModeCoefficients(double lambda, double kT, double h) {
    ModeCoefficients c;
    double x = lambda*h;
    c.lambda = lambda;
    c.decay = std::exp(-x);
    if (x == 0) {
        c.drift = h;
        c.noiseVelocity = c.noiseCross = c.noiseDisplacement = 0;
        return c;
    }
    double oneMinusDecay = -std::expm1(-x);
    c.drift = h*oneMinusDecay/x;
    double varW = -kT*std::expm1(-2*x);
    double covWY = kT*h*oneMinusDecay*oneMinusDecay/x;
    double varY = kT*h*h*displacementVarianceFactor(x);
    c.noiseVelocity = std::sqrt(varW);
    c.noiseCross = (varW > 0 ? covWY/c.noiseVelocity : 0.0);
    c.noiseDisplacement = std::sqrt(std::max(0.0, varY-c.noiseCross*c.noiseCross));
    return c;
}

double RigidLangevinPlugin::synchronousShare(double x) {
    if (x < 1e-3)
        return 0.5-x/12+x*x*x/720;  // the next term, x^5/30240, is below 4e-20
    if (x > 700)
        return 1/x;
    return 1/x-1/std::expm1(x);
}

vector<TypeStepCoefficients> RigidLangevinPlugin::computeStepCoefficients(const RigidBodyModel& model, SplittingScheme scheme,
        double temperature, double viscosity, double stepSize) {
    const double kT = BOLTZ*temperature;
    vector<TypeStepCoefficients> result(model.getNumTypes());
    for (int t = 0; t < model.getNumTypes(); t++) {
        const BodyType& type = model.getType(t);
        TypeStepCoefficients& c = result[t];
        vector<int> active = type.getActiveCoordinates();
        int dof = active.size();
        c.frictionClass = type.frictionClass;
        Eigen::VectorXd mass(dof);
        for (int i = 0; i < dof; i++) {
            mass[i] = (active[i] < 3 ? type.mass : type.inertia[active[i]-3]);
            c.inverseMass[i] = 1/mass[i];
        }
        Eigen::MatrixXd xi(dof, dof);
        for (int i = 0; i < dof; i++)
            for (int j = 0; j < dof; j++)
                xi(i, j) = viscosity*type.resistance(active[i], active[j]);

        // Modes of K = M^-1/2 (viscosity Xi) M^-1/2.
        Eigen::VectorXd invSqrtMass = mass.cwiseSqrt().cwiseInverse();
        Eigen::MatrixXd k = invSqrtMass.asDiagonal()*xi*invSqrtMass.asDiagonal();
        Eigen::VectorXd lambda(dof);
        Eigen::MatrixXd s = Eigen::MatrixXd::Identity(dof, dof);
        if (type.frictionClass == FrictionClass::Coupled) {
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(k);
            lambda = eigen.eigenvalues();
            s = eigen.eigenvectors();
        }
        else
            lambda = k.diagonal();
        c.toModes = Matrix6::Zero();
        c.fromModes = Matrix6::Zero();
        c.toModes.topLeftCorner(dof, dof) = s.transpose()*mass.cwiseSqrt().asDiagonal();
        c.fromModes.topLeftCorner(dof, dof) = invSqrtMass.asDiagonal()*s;
        double lambdaMax = 0;
        c.halfSteps = (scheme == SplittingScheme::ExactFlow && type.numRotations > 0);
        double modeStep = (c.halfSteps ? 0.5*stepSize : stepSize);
        for (int i = 0; i < 6; i++)
            c.modes[i] = computeModeCoefficients(i < dof ? std::max(0.0, lambda[i]) : 0.0, kT, modeStep);
        for (int k = 0; k < 6; k++) {
            double m = (k < 3 ? type.mass : type.inertia[k-3]);
            double x = (m > 0 ? stepSize*viscosity*type.resistance(k, k)/m : 0.0);
            c.driveFraction[k] = (x == 0 ? 1.0 : -2*std::expm1(-0.5*x)/x);
        }
        c.mobility = Matrix6::Zero();
        c.mobilityFactor = Matrix6::Zero();
        if (scheme == SplittingScheme::Overdamped) {
            Eigen::LLT<Eigen::MatrixXd> friction(xi);
            if (friction.info() != Eigen::Success || !(viscosity > 0))
                throw OpenMMException("RigidBrownianIntegrator: the friction of "+model.getBodyName(model.getFirstBodyOfType(t))+" is not positive definite "
                        "(the viscosity must be positive for overdamped dynamics)");
            Eigen::MatrixXd mobility = friction.solve(Eigen::MatrixXd::Identity(dof, dof));
            mobility = 0.5*(mobility+mobility.transpose());
            c.mobility.topLeftCorner(dof, dof) = mobility;
            c.mobilityFactor.topLeftCorner(dof, dof) = Eigen::MatrixXd(mobility.llt().matrixL());
        }
        Eigen::VectorXd share = Eigen::VectorXd::Constant(dof, scheme == SplittingScheme::Overdamped ? 0.0 : 0.5);
        if (scheme == SplittingScheme::ExactFlow)
            for (int i = 0; i < dof; i++)
                share[i] = synchronousShare(stepSize*std::max(0.0, lambda[i]));
        c.synchronousKick = Matrix6::Zero();
        c.synchronousKick.topLeftCorner(dof, dof) = c.fromModes.topLeftCorner(dof, dof)*share.asDiagonal()*c.toModes.topLeftCorner(dof, dof);
        for (int i = 0; i < dof; i++)
            lambdaMax = std::max(lambdaMax, lambda[i]);
        c.stiffness = 0.5*stepSize*lambdaMax;

        // The Original scheme's explicit friction and random force.
        c.friction = Matrix6::Zero();
        c.randomForce = Matrix6::Zero();
        c.friction.topLeftCorner(dof, dof) = xi;
        if (scheme == SplittingScheme::Original && viscosity > 0) {
            Eigen::LLT<Eigen::MatrixXd> llt(xi);
            c.randomForce.topLeftCorner(dof, dof) = std::sqrt(2*kT/stepSize)*Eigen::MatrixXd(llt.matrixL());
        }
    }
    return result;
}

void RigidLangevinPlugin::checkOriginalSchemeStability(const RigidBodyModel& model, const vector<TypeStepCoefficients>& coefficients, double stepSize) {
    for (int b = 0; b < model.getNumBodies(); b++) {
        const TypeStepCoefficients& c = coefficients[model.getBodyType(b)];
        if (c.stiffness >= 1) {
            std::ostringstream message;
            message << "RigidLangevinIntegrator: the Original scheme cannot integrate "
                    << (b < model.getNumUserBodies() ? "rigid body " : "the free particle of body ") << b
                    << ": its friction is too stiff for the step, (h/2)*lambda_max(M^-1 viscosity Xi) = " << c.stiffness
                    << " >= 1, where the fixed-point iteration for the friction diverges. Use the default ExactFlow scheme, "
                    << "which is exact at any friction, or a step below " << stepSize/c.stiffness << " ps";
            throw OpenMMException(message.str());
        }
    }
}
