/*
 * The integrator's default hydrodynamics: a multi-particle body is a Rotne-Prager-Yamakawa bead
 * model of its particles with the volume correction of a filling model (V the union of their
 * spheres), computed once per body type; setBodyHydrodynamics() takes any model.
 */
#include "ReferenceTests.h"
#include "ResistanceTensor.h"
#include "RigidBodyTestUtilities.h"
#include "internal/RigidBodyModel.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <Eigen/Geometry>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

TEST(DefaultHydrodynamics, UnionVolumeOfTwoSpheres) {
    // Two spheres of radius r at distance d overlap in a lens of volume pi (4r + d)(2r - d)^2/12.
    for (double d : {0.0, 0.05, 0.1, 0.19, 0.3}) {
        double r = 0.1;
        double lens = (d < 2*r ? M_PI*(4*r+d)*(2*r-d)*(2*r-d)/12 : 0.0);
        double exact = 2*4*M_PI*r*r*r/3-lens;
        double v = ResistanceTensor::unionVolume({Vec3(0, 0, 0), Vec3(d, 0, 0)}, {r, r});
        EXPECT_NEAR(exact, v, 1e-3*exact) << "d = " << d;
    }
    // A sphere inside another adds nothing.
    EXPECT_NEAR(4*M_PI/3*0.008, ResistanceTensor::unionVolume({Vec3(), Vec3(0.05, 0, 0)}, {0.2, 0.1}), 1e-3*4*M_PI/3*0.008);
    EXPECT_THROW(ResistanceTensor::unionVolume({Vec3()}, {-1.0}), OpenMMException);
}

TEST(DefaultHydrodynamics, BodiesAreBeadModelsOfTheirParticles) {
    // A bent three-particle body with one massless site that has no radius: its type's tensor (body
    // frame, about the centre of mass) equals beads() of the particles with radii, corrected by
    // their union volume, expressed the same way.
    System system;
    for (double m : {16.0, 1.0, 1.0, 0.0})
        system.addParticle(m);
    // The model is built from a plain description of the bodies: no integrator is needed.
    RigidBodyDescription description;
    description.bodies.resize(1);
    description.bodies[0].particles = {0, 1, 2, 3};
    std::vector<double> radii = {0.15, 0.12, 0.12};
    for (int i = 0; i < 3; i++)
        description.particleRadii[i] = radii[i];
    std::vector<Vec3> positions = {Vec3(0.1, 0.2, 0.3), Vec3(0.1957, 0.2, 0.3), Vec3(0.076, 0.2927, 0.3), Vec3(0.11, 0.21, 0.3)};
    RigidBodyModel model(system, description);
    std::vector<BodyState> states = model.fitStates(positions, std::vector<Vec3>(4), NULL);
    ASSERT_EQ(1, model.getNumTypes());
    const BodyType& type = model.getType(0);
    std::vector<Vec3> beads(positions.begin(), positions.begin()+3);
    // The same volume as the model's (it integrates in the body frame; the grid makes it depend on
    // the frame by ~0.1%).
    std::vector<Vec3> bodyFrame(type.coords.begin(), type.coords.begin()+3);
    double volume = ResistanceTensor::unionVolume(bodyFrame, radii);
    EXPECT_NEAR(ResistanceTensor::unionVolume(beads, radii), volume, 2e-3*volume);
    ResistanceTensor expected = ResistanceTensor::beads(beads, radii, volume);
    std::vector<double> atCenter = expected.getMatrix(states[0].position);
    Eigen::Matrix<double, 6, 6> lab = Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(atCenter.data());
    Eigen::Matrix<double, 6, 6> rotation = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            rotation(i, j) = rotation(3+i, 3+j) = states[0].rotation[i][j];
    Eigen::Matrix<double, 6, 6> body = rotation*lab*rotation.transpose();
    EXPECT_LT((body-type.resistance).cwiseAbs().maxCoeff(), 1e-10*body.cwiseAbs().maxCoeff());
    // The correction made the rotation block larger than the beads' alone.
    std::vector<double> bare = ResistanceTensor::beads(beads, radii).getMatrix();
    EXPECT_GT(lab(3, 3)+lab(4, 4)+lab(5, 5), bare[21]+bare[28]+bare[35]);
}

TEST(DefaultHydrodynamics, IdenticalBodiesShareOneType) {
    // 200 waters in random orientations and positions are one type (one hydrodynamic calculation);
    // free particles of one mass and radius are another; a body and its mirror image are two.
    BodyShape water({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.09572, 0, 0), Eigen::Vector3d(-0.024, 0.0927, 0)}, {15.999, 1.008, 1.008});
    System system;
    RigidLangevinIntegrator integrator(300, 500, 0.002);
    std::vector<Vec3> positions;
    for (int b = 0; b < 200; b++) {
        Eigen::Matrix3d r = Eigen::AngleAxisd(0.77*b, Eigen::Vector3d(std::sin(b), std::cos(b), 0.3).normalized()).toRotationMatrix();
        std::vector<int> particles;
        for (int i = 0; i < 3; i++) {
            particles.push_back(system.addParticle(water.masses[i]));
            integrator.setParticleRadius(particles.back(), i == 0 ? 0.1575 : 0.12);
            positions.push_back(toVec3(r*water.reference[i]+Eigen::Vector3d(b, 0.5*b, 0)));
        }
        integrator.addRigidBody(particles);
    }
    for (int i = 0; i < 10; i++) {
        integrator.setParticleRadius(system.addParticle(20.0), 0.15);
        positions.push_back(Vec3(i, -3, 0));
    }
    Context context(system, integrator, Platform::getPlatformByName("Reference"));
    context.setPositions(positions);
    EXPECT_EQ(2, integrator.getNumBodyTypes());

    // A chiral four-particle body and its mirror image.
    System chiral;
    RigidLangevinIntegrator integrator2(300, 500, 0.002);
    std::vector<Vec3> chiralPositions;
    BodyShape shape = asymmetricBody();
    for (int mirror = 0; mirror < 2; mirror++) {
        std::vector<int> particles;
        for (int i = 0; i < 4; i++) {
            particles.push_back(chiral.addParticle(shape.masses[i]));
            integrator2.setParticleRadius(particles.back(), 0.1);
            Eigen::Vector3d p = shape.reference[i];
            if (mirror)
                p[2] = -p[2];
            chiralPositions.push_back(toVec3(p+Eigen::Vector3d(2.0*mirror, 0, 0)));
        }
        integrator2.addRigidBody(particles);
    }
    Context context2(chiral, integrator2, Platform::getPlatformByName("Reference"));
    context2.setPositions(chiralPositions);
    EXPECT_EQ(2, integrator2.getNumBodyTypes());
}

TEST(DefaultHydrodynamics, SetBodyHydrodynamicsTakesAnyModel) {
    RigidLangevinIntegrator integrator(300, 100, 0.002);
    integrator.addRigidBody({0, 1});
    ResistanceTensor ellipsoid = ResistanceTensor::ellipsoid(0.3, 0.2, 0.1, Vec3(0.1, 0, 0));
    std::vector<Vec3> reference = {Vec3(-0.2, 0, 0), Vec3(0.4, 0, 0)};
    integrator.setBodyHydrodynamics(0, ellipsoid, reference);
    std::vector<double> tensor;
    Vec3 origin;
    std::vector<Vec3> r;
    ASSERT_TRUE(integrator.getBodyResistance(0, tensor, origin, r));
    EXPECT_EQ(ellipsoid.getMatrix(), tensor);
    EXPECT_EQ(ellipsoid.getOrigin(), origin);
    EXPECT_EQ(reference, r);
    EXPECT_THROW(integrator.setBodyHydrodynamics(0, ResistanceTensor(), reference), OpenMMException);
}
