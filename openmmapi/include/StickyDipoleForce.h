#ifndef RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_H_
#define RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_H_

/* -------------------------------------------------------------------------- *
 *                        openmm-rigid-langevin                               *
 * -------------------------------------------------------------------------- */

#include "openmm/Force.h"
#include "internal/windowsExportRigidLangevin.h"
#include <string>
#include <utility>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The soft sticky dipole (SSD) family of single-site water models (SSD: Liu & Ichiye, J. Phys.
 * Chem. 100, 2723 (1996); SSD1: Tan et al., Chem. Phys. Lett. 376, 646 (2003); SSD/E and SSD/RF:
 * Fennell & Gezelter, J. Chem. Phys. 120, 9175 (2004)), or any sites with parameters of that form.
 *
 * Each site is a particle with a Lennard-Jones sphere, a point dipole and a "sticky" tetrahedral
 * term, all oriented by the site's body frame. The frame comes from two reference particles of the
 * site's own molecule (for water, its two hydrogens, which interact with nothing else), the way
 * GayBerneForce takes an ellipsoid's axes:
 *
 *     z = the unit vector from the site to the midpoint of the two reference particles
 *         (the dipole's direction: from oxygen towards the hydrogens),
 *     y = the unit vector along (first reference - second reference), made perpendicular to z
 *         (the molecular plane is the yz-plane),
 *     x = y cross z.
 *
 * The energy depends on the reference particles' positions only through the frame; the forces on
 * them are its exact gradient, so the force works under any integrator that keeps the molecule
 * rigid (this plugin's bodies, or OpenMM's integrators with constraints).
 *
 * A pair of sites i, j at separation d = r_j - r_i (r = |d|) interacts through
 *
 *     U = S(r) [U_LJ + U_dipole] + U_sticky
 *     U_LJ     = 4 eps [(sigma/r)^12 - (sigma/r)^6],  sigma = (sigma_i+sigma_j)/2, eps = sqrt(eps_i eps_j)
 *     U_dipole = k [mu_i.mu_j/r^3 - 3 (mu_i.d)(mu_j.d)/r^5 - 2 kappa mu_i.mu_j],  mu = dipole * z
 *     U_sticky = 1/2 sum over m in {i, j} of [nu0_m s_m(r) w_m + nu0'_m s'_m(r) w'_m]
 *
 * with k = 138.935456 kJ nm/(mol e^2) (1/(4 pi eps0)), kappa = (eps_RF-1)/((2 eps_RF+1) r_c^3) the
 * reaction field of a dielectric continuum beyond the cutoff (0 without a cutoff), and, in the
 * frame of molecule m, (x, y, z) = A_i d for i and -A_j d for j (each sees the other):
 *
 *     w  = 2 (x^2 - y^2) z / r^3                          (= sin(theta) sin(2 theta) cos(2 phi))
 *     w' = (z/r - 0.6)^2 (z/r + 0.8)^2 - w0
 *     s(r) = 1 below rL, (rU-r)^2 (rU+2r-3rL)/(rU-rL)^3 between rL and rU, 0 beyond; s' with rL', rU'.
 *
 * For sites of one kind the sticky term is the published one; sites of different kinds each
 * contribute their own half. With a cutoff, S(r) is the same cubic switch from the switching
 * distance to the cutoff (1 everywhere if switching is off), and each site adds the reaction
 * field's self energy -k kappa dipole^2. Excluded pairs do not interact. A periodic cutoff may not
 * exceed half the box's width (checked whenever the energy is computed).
 *
 * This is the form of the source's own code (OOPSE, OpenMD's predecessor, at the commit of its
 * Langevin integrator, December 2008: electrostatic.F90, sticky.F90, switcheroo.F90): the dipole
 * pair term with -2 kappa mu_i.mu_j, the self term -kappa mu^2, the cubic switch from the switching
 * radius to the cutoff. OOPSE multiplied the sticky term by the switch too; the switch is 1 wherever
 * the sticky term is nonzero as long as the switching distance is at least rU and rU' (0.4 nm for
 * the published models; the source switched from 0.85 r_c = 0.765 nm), and this force leaves it
 * unswitched. Today's OpenMD shifts the reaction field instead (its dipole terms carry 1/r_c^3 in
 * place of -2 kappa): a different model, not this one.
 *
 * Units are OpenMM's: nm, kJ/mol, dipole moments in e*nm (1 D = 0.0208194 e*nm).
 */
class OPENMM_EXPORT_RIGIDLANGEVIN StickyDipoleForce : public OpenMM::Force {
public:
    /** How interactions are cut off (the meanings of NonbondedForce's methods of these names). */
    enum NonbondedMethod {
        NoCutoff = 0,
        CutoffNonPeriodic = 1,
        CutoffPeriodic = 2
    };
    /** The parameters of one site. Lengths in nm, energies in kJ/mol, the dipole in e*nm. */
    struct SiteParameters {
        double sigma, epsilon, dipole;
        double nu0, rL, rU;                ///< the tetrahedral term w and its switch s(r) (rL < rU unless nu0 = 0)
        double nu0Prime, rLPrime, rUPrime; ///< the dipole-alignment term w' and its switch s'(r) (rL' < rU' unless nu0' = 0)
        double w0;                         ///< the offset of w' (0.07715 for the SSD family)
        SiteParameters();
    };
    /**
     * The parameters of a named SSD-family model: "SSD" (Liu & Ichiye 1996, as tabulated with SSD1),
     * "SSD1" (Tan et al. 2003), "SSD/E" or "SSD/RF" (Fennell & Gezelter 2004); the same values as
     * OpenMD's forceFields/Water.frc. The point quadrupole OpenMD also gives these types is not
     * modelled: neat SSD water interacts through its dipole.
     */
    static SiteParameters getModelParameters(const std::string& model);

    StickyDipoleForce();
    /**
     * Add a site.
     *
     * @param particle   the particle carrying the site
     * @param reference1 the first reference particle of its frame (in its molecule)
     * @param reference2 the second reference particle
     * @param parameters the site's parameters
     * @return the index of the site
     */
    int addSite(int particle, int reference1, int reference2, const SiteParameters& parameters);
    /** Get the number of sites that have been added. */
    int getNumSites() const {
        return sites.size();
    }
    /** Get a site's particle, the two reference particles of its frame and its parameters. */
    void getSiteParameters(int index, int& particle, int& reference1, int& reference2, SiteParameters& parameters) const;
    /**
     * Replace a site's particle, frame and parameters. A Context made before sees the change only
     * after Context.reinitialize().
     */
    void setSiteParameters(int index, int particle, int reference1, int reference2, const SiteParameters& parameters);
    /**
     * Exclude the interaction between two sites (indices of sites, not particles). On the OpenCL and
     * CUDA platforms, whose nonbonded kernel this force shares, a force with exclusions must have the
     * same exclusions (between the same particles) as every other nonbonded force in the System that
     * uses any: OpenMM's rule for that kernel, which says so when it is broken.
     */
    int addExclusion(int site1, int site2);
    /** Get the number of exclusions that have been added. */
    int getNumExclusions() const {
        return exclusions.size();
    }
    /** Get the two sites (indices of sites, not particles) of an exclusion. */
    void getExclusionSites(int index, int& site1, int& site2) const;
    /** Get how pairs are cut off and whether the box is periodic (NoCutoff, CutoffNonPeriodic or CutoffPeriodic). */
    NonbondedMethod getNonbondedMethod() const {
        return method;
    }
    /** Set how pairs are cut off and whether the box is periodic (NoCutoff, CutoffNonPeriodic or CutoffPeriodic). */
    void setNonbondedMethod(NonbondedMethod method);
    /** The cutoff distance (nm), used by the cutoff methods. */
    double getCutoffDistance() const {
        return cutoff;
    }
    /** Set the cutoff distance (nm), used by the cutoff methods. */
    void setCutoffDistance(double distance);
    /** Whether pair energies are switched smoothly to zero between the switching distance and the cutoff. */
    bool getUseSwitchingFunction() const {
        return useSwitching;
    }
    /** Set whether pair energies are switched smoothly to zero between the switching distance and the cutoff. */
    void setUseSwitchingFunction(bool use);
    /** The distance (nm) at which the switch begins; less than the cutoff. */
    double getSwitchingDistance() const {
        return switchingDistance;
    }
    /** Set the distance (nm) at which the switch begins; less than the cutoff. */
    void setSwitchingDistance(double distance);
    /** The dielectric constant of the continuum beyond the cutoff (default 80; 1 gives no reaction field). */
    double getReactionFieldDielectric() const {
        return reactionFieldDielectric;
    }
    /** Set the dielectric constant of the continuum beyond the cutoff (1 gives no reaction field). */
    void setReactionFieldDielectric(double dielectric);
    /** Whether the force uses periodic boundary conditions (the CutoffPeriodic method). */
    bool usesPeriodicBoundaryConditions() const {
        return method == CutoffPeriodic;
    }
protected:
    OpenMM::ForceImpl* createImpl() const;
private:
    struct Site {
        int particle, reference1, reference2;
        SiteParameters parameters;
    };
    std::vector<Site> sites;
    std::vector<std::pair<int, int> > exclusions;
    NonbondedMethod method;
    double cutoff, switchingDistance, reactionFieldDielectric;
    bool useSwitching;
};

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_H_*/
