// HSLocalForces (hs_local_forces.h): forces of V_C, the interaction terms
// with an atom of C, through the styles' own compute() on restricted lists.
// Exactness: every term acting on an atom of C involves it, so the restricted
// force on each atom of C must equal LAMMPS' full force on it (to round-off,
// the summation order differs). Partners: against an independent brute-force
// sum over minimum-image LJ pairs with an atom of C (fluid), and the total
// force of V_C vanishing (every term's forces sum to zero; melt). LAMMPS'
// state (atom->f of owned and ghost atoms, the styles' tallies) must be
// bit-identical after each call. Cases: LJ fluid with newton on / off,
// bead-spring melt (bonds, angles, dihedrals) with chains across the
// periodic boundary, random C of sizes 1 .. all, atoms near the boundaries;
// styles that cannot be restricted are reported. Under mpirun (unittest/mpi/
// test_mpi_local_forces.sh) every rank passes its own C; the checks on C,
// the state and the vanishing total force hold on every rank count.

#include "hs_test_main.h"

#include "library.h"

#include "hs_local_forces.h"
#include "hs_mpi.h"

#include "angle.h"
#include "atom.h"
#include "bond.h"
#include "comm.h"
#include "dihedral.h"
#include "domain.h"
#include "force.h"
#include "group.h"
#include "neighbor.h"
#include "pair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

using LAMMPS_NS::HSLocalForces;

namespace {

struct Snapshot {
  std::vector<double> f;
  double tal[5][8];
};

void tallies(LAMMPS_NS::LAMMPS *lmp, double out[5][8])
{
  auto *force = lmp->force;
  memset(out, 0, sizeof(double) * 40);
  if (force->pair) {
    out[0][0] = force->pair->eng_vdwl;
    out[0][1] = force->pair->eng_coul;
    for (int k = 0; k < 6; k++) out[0][2 + k] = force->pair->virial[k];
  }
  if (force->bond) {
    out[1][0] = force->bond->energy;
    for (int k = 0; k < 6; k++) out[1][2 + k] = force->bond->virial[k];
  }
  if (force->angle) {
    out[2][0] = force->angle->energy;
    for (int k = 0; k < 6; k++) out[2][2 + k] = force->angle->virial[k];
  }
  if (force->dihedral) {
    out[3][0] = force->dihedral->energy;
    for (int k = 0; k < 6; k++) out[3][2 + k] = force->dihedral->virial[k];
  }
}

Snapshot snap(LAMMPS_NS::LAMMPS *lmp)
{
  Snapshot s;
  auto *atom = lmp->atom;
  const int nall = atom->nlocal + atom->nghost;
  s.f.assign(&atom->f[0][0], &atom->f[0][0] + 3 * nall);
  tallies(lmp, s.tal);
  return s;
}

void expect_unchanged(LAMMPS_NS::LAMMPS *lmp, const Snapshot &s, const std::string &what)
{
  Snapshot t = snap(lmp);
  ASSERT_EQ(s.f.size(), t.f.size());
  EXPECT_EQ(0, memcmp(s.f.data(), t.f.data(), s.f.size() * sizeof(double)))
      << what << ": atom->f changed";
  EXPECT_EQ(0, memcmp(s.tal, t.tal, sizeof(s.tal))) << what << ": tallies changed";
}

// C: random owned atoms, plus (boundary) atoms within 0.6 of a box face
std::vector<int> random_c(LAMMPS_NS::LAMMPS *lmp, int n, unsigned seed, bool boundary)
{
  auto *atom = lmp->atom;
  auto *domain = lmp->domain;
  std::mt19937 rng(seed);
  std::vector<int> all(atom->nlocal);
  for (int i = 0; i < atom->nlocal; i++) all[i] = i;
  std::shuffle(all.begin(), all.end(), rng);
  std::vector<int> c;
  if (boundary) {
    for (int i : all) {
      const double *x = atom->x[i];
      bool near = false;
      for (int k = 0; k < 3; k++)
        near = near || x[k] - domain->boxlo[k] < 0.6 || domain->boxhi[k] - x[k] < 0.6;
      if (near && (int) c.size() < n) c.push_back(i);
    }
  } else {
    c.assign(all.begin(), all.begin() + std::min<int>(n, atom->nlocal));
  }
  return c;
}

// forces on C equal the full forces; state unchanged; returns the largest
// relative deviation
double check_c(HSLammps &h, HSLocalForces &lf, const std::vector<int> &c, const std::string &what)
{
  auto *atom = h.lmp->atom;
  const Snapshot before = snap(h.lmp);
  lf.compute(c.data(), (int) c.size());
  expect_unchanged(h.lmp, before, what);
  double **fl = lf.forces();
  double fscale = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 3; k++) fscale = std::max(fscale, std::fabs(atom->f[i][k]));
  std::set<int> touched(lf.touched().begin(), lf.touched().end());
  double worst = 0.0;
  for (int i : c) {
    EXPECT_TRUE(touched.count(i)) << what << ": atom of C not reported";
    for (int k = 0; k < 3; k++) {
      const double d = std::fabs(fl[i][k] - atom->f[i][k]) / fscale;
      worst = std::max(worst, d);
      EXPECT_LT(d, 1e-13) << what << ": atom tag " << atom->tag[i] << " dim " << k << " local "
                          << fl[i][k] << " full " << atom->f[i][k];
    }
  }
  return worst;
}

std::string fluid_input(bool newton)
{
  return std::string("units lj\natom_style atomic\natom_modify map array\nboundary p p p\n") +
      (newton ? "newton on\n" : "newton off\n") +
      "lattice fcc 0.5729578\nregion box block 0 4 0 4 0 4\ncreate_box 1 box\n"
      "create_atoms 1 box\nmass 1 1.0\n"
      "displace_atoms all random 0.15 0.15 0.15 4711 units box\n"
      "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0 2.5\npair_modify shift yes\n"
      "neighbor 0.3 bin\nrun 0\n";
}

// -grad V_C by brute force: minimum-image LJ pairs (r < 2.5) of n points
// x[3 n] in the box of lmp, where in_c(i) or in_c(j)
template <class InC>
std::vector<double> brute_lj_points(LAMMPS_NS::LAMMPS *lmp, const double *x, int n, InC in_c)
{
  auto *domain = lmp->domain;
  const double L[3] = {domain->xprd, domain->yprd, domain->zprd};
  std::vector<double> f(3 * n, 0.0);
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      if (!in_c(i) && !in_c(j)) continue;
      double d[3], r2 = 0.0;
      for (int k = 0; k < 3; k++) {
        d[k] = x[3 * i + k] - x[3 * j + k];
        d[k] -= L[k] * std::round(d[k] / L[k]);
        r2 += d[k] * d[k];
      }
      if (r2 >= 2.5 * 2.5) continue;
      const double ir6 = 1.0 / (r2 * r2 * r2);
      const double fr = 24.0 * ir6 * (2.0 * ir6 - 1.0) / r2;
      for (int k = 0; k < 3; k++) {
        f[3 * i + k] += fr * d[k];
        f[3 * j + k] -= fr * d[k];
      }
    }
  return f;
}

// the same over this rank's owned atoms (serial: all), C by local index
std::vector<double> brute_lj(LAMMPS_NS::LAMMPS *lmp, const std::vector<int> &c)
{
  auto *atom = lmp->atom;
  const int n = atom->nlocal;
  std::vector<char> inc(n, 0);
  for (int i : c) inc[i] = 1;
  return brute_lj_points(lmp, &atom->x[0][0], n, [&](int i) { return inc[i] != 0; });
}

}    // namespace

class LocalForcesFluid : public ::testing::TestWithParam<bool> {};

TEST_P(LocalForcesFluid, ExactOnCAndPartners)
{
  const bool newton = GetParam();
  HSLammps h;
  h.lines(fluid_input(newton));
  auto *atom = h.lmp->atom;
  HSLocalForces lf(h.lmp, "test");
  lf.init();
  ASSERT_TRUE(lf.exact()) << lf.unrestrictable();
  double worst = 0.0;
  int cases = 0;
  for (int n : {1, 2, 5, 20, 100, atom->nlocal})
    for (unsigned seed = 1; seed <= 3; seed++)
      for (bool boundary : {false, true}) {
        const auto c = random_c(h.lmp, n, seed * 31 + n, boundary);
        if (c.empty()) continue;
        const std::string what = "newton " + std::to_string(newton) + " |C| " +
            std::to_string(c.size()) + (boundary ? " boundary" : "");
        worst = std::max(worst, check_c(h, lf, c, what));
        ++cases;
        // partners: against the brute-force -grad V_C on every owned atom
        // (the brute force sees only this rank's atoms: serial runs only)
        if (h.lmp->comm->nprocs > 1) continue;
        const auto ref = brute_lj(h.lmp, c);
        std::set<int> touched(lf.touched().begin(), lf.touched().end());
        double fscale = 1.0;
        for (double v : ref) fscale = std::max(fscale, std::fabs(v));
        for (int i = 0; i < atom->nlocal; i++) {
          const bool nonzero = ref[3 * i] != 0.0 || ref[3 * i + 1] != 0.0 || ref[3 * i + 2] != 0.0;
          if (!touched.count(i)) {
            EXPECT_FALSE(nonzero) << what << ": partner tag " << atom->tag[i] << " missing";
            continue;
          }
          for (int k = 0; k < 3; k++)
            EXPECT_NEAR(lf.forces()[i][k], ref[3 * i + k], 1e-12 * fscale)
                << what << ": tag " << atom->tag[i] << " dim " << k;
        }
      }
  EXPECT_GE(cases, 30);
  EXPECT_LT(worst, 1e-13);
  // the restricted evaluation is local: |C| = 1 evaluates O(neighbours) pairs
  if (h.lmp->comm->nprocs > 1) return;
  const double before = lf.npair_terms;
  const auto one = random_c(h.lmp, 1, 5, false);
  lf.compute(one.data(), 1);
  EXPECT_LT(lf.npair_terms - before, 120.0);
  EXPECT_GT(lf.npair_terms - before, 20.0);
}

INSTANTIATE_TEST_SUITE_P(Newton, LocalForcesFluid, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool> &i) {
                           return std::string(i.param ? "on" : "off");
                         });

namespace {

// bead-spring melt: NCH chains of NB beads on a simple cubic lattice
// (spacing 1), along x and shifted by half the box so that every chain
// crosses the periodic boundary; bonds, angles, dihedrals
std::string melt_data(const std::string &path)
{
  const int NB = 8, NY = 5, NZ = 5;
  const double Lx = NB, Ly = NY, Lz = NZ;
  FILE *fp = fopen(path.c_str(), "w");
  const int nat = NB * NY * NZ, nch = NY * NZ;
  fprintf(fp, "melt\n\n%d atoms\n%d bonds\n%d angles\n%d dihedrals\n1 atom types\n1 bond types\n"
              "1 angle types\n1 dihedral types\n\n0 %g xlo xhi\n0 %g ylo yhi\n0 %g zlo zhi\n\n"
              "Masses\n\n1 1.0\n\nAtoms # molecular\n\n",
          nat, nch * (NB - 1), nch * (NB - 2), nch * (NB - 3), Lx, Ly, Lz);
  int tag = 0;
  for (int k = 0; k < NZ; k++)
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NB; i++) {
        ++tag;
        double x = std::fmod(i + 0.5 + 0.5 * Lx, Lx);
        fprintf(fp, "%d %d 1 %.10f %.10f %.10f\n", tag, 1 + (tag - 1) / NB, x, j + 0.5, k + 0.5);
      }
  fprintf(fp, "\nBonds\n\n");
  int b = 0;
  for (int c = 0; c < nch; c++)
    for (int m = 0; m + 1 < NB; m++) fprintf(fp, "%d 1 %d %d\n", ++b, c * NB + m + 1, c * NB + m + 2);
  fprintf(fp, "\nAngles\n\n");
  b = 0;
  for (int c = 0; c < nch; c++)
    for (int m = 0; m + 2 < NB; m++)
      fprintf(fp, "%d 1 %d %d %d\n", ++b, c * NB + m + 1, c * NB + m + 2, c * NB + m + 3);
  fprintf(fp, "\nDihedrals\n\n");
  b = 0;
  for (int c = 0; c < nch; c++)
    for (int m = 0; m + 3 < NB; m++)
      fprintf(fp, "%d 1 %d %d %d %d\n", ++b, c * NB + m + 1, c * NB + m + 2, c * NB + m + 3,
              c * NB + m + 4);
  fclose(fp);
  return path;
}

std::string melt_input(const std::string &data, bool newton)
{
  // the random displacements make the chains non-collinear (dihedrals defined)
  return std::string("units lj\natom_style molecular\nboundary p p p\n") +
      (newton ? "newton on\n" : "newton off\n") + "read_data " + data +
      "\ndisplace_atoms all random 0.12 0.12 0.12 1234 units box\n"
      "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0 2.5\npair_modify shift yes\n"
      "bond_style harmonic\nbond_coeff 1 300.0 0.97\n"
      "angle_style harmonic\nangle_coeff 1 5.0 120.0\n"
      "dihedral_style harmonic\ndihedral_coeff 1 1.5 1 2\n"
      "special_bonds lj 0.0 1.0 1.0\nneighbor 0.3 bin\ncomm_modify cutoff 4.0\nrun 0\n";
}

}    // namespace

class LocalForcesMelt : public ::testing::TestWithParam<bool> {};

TEST_P(LocalForcesMelt, BondedTermsExact)
{
  const bool newton = GetParam();
  const std::string data = melt_data(scratch_name("melt.data"));
  HSLammps h;
  h.lines(melt_input(data, newton));
  remove(data.c_str());
  auto *atom = h.lmp->atom;
  int ndih = h.lmp->neighbor->ndihedrallist, ndih_all = 0;
  MPI_Allreduce(&ndih, &ndih_all, 1, MPI_INT, MPI_SUM, h.lmp->world);
  ASSERT_GT(ndih_all, 0);
  HSLocalForces lf(h.lmp, "test");
  lf.init();
  ASSERT_TRUE(lf.exact()) << lf.unrestrictable();
  double worst = 0.0;
  for (int n : {1, 3, 10, 50, atom->nlocal})
    for (unsigned seed = 1; seed <= 3; seed++)
      for (bool boundary : {false, true}) {
        const auto c = random_c(h.lmp, n, seed * 7 + n, boundary);
        if (c.empty()) continue;
        const std::string what = "melt newton " + std::to_string(newton) + " |C| " +
            std::to_string(c.size()) + (boundary ? " boundary" : "");
        const double b0 = lf.nbonded_terms;
        worst = std::max(worst, check_c(h, lf, c, what));
        double nb = lf.nbonded_terms - b0, nb_all = 0.0;
        MPI_Allreduce(&nb, &nb_all, 1, MPI_DOUBLE, MPI_SUM, h.lmp->world);
        EXPECT_GT(nb_all, 0.0) << what << ": no bonded term restricted";
        // every term's forces sum to zero, so V_C's total force vanishes:
        // a partner's missing contribution would show here
        double sum[3] = {0, 0, 0}, scale = 0.0;
        for (int i : lf.touched())
          for (int k = 0; k < 3; k++) {
            sum[k] += lf.forces()[i][k];
            scale = std::max(scale, std::fabs(lf.forces()[i][k]));
          }
        double all[4], one[4] = {sum[0], sum[1], sum[2], 0.0};
        MPI_Allreduce(one, all, 3, MPI_DOUBLE, MPI_SUM, h.lmp->world);
        MPI_Allreduce(&scale, &all[3], 1, MPI_DOUBLE, MPI_MAX, h.lmp->world);
        for (int k = 0; k < 3; k++) EXPECT_LT(std::fabs(all[k]), 1e-11 * all[3]) << what;
      }
  EXPECT_LT(worst, 1e-13);
  // C = all atoms: every atom's force is the full force
  std::vector<int> all(atom->nlocal);
  for (int i = 0; i < atom->nlocal; i++) all[i] = i;
  check_c(h, lf, all, "melt all");
}

INSTANTIATE_TEST_SUITE_P(Newton, LocalForcesMelt, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool> &i) {
                           return std::string(i.param ? "on" : "off");
                         });

// after atoms move and the lists are rebuilt, the inverse index follows
TEST(LocalForces, AfterReneighboring)
{
  HSLammps h;
  h.lines(fluid_input(true));
  h.lines("velocity all create 2.0 5 mom yes\nfix 1 all nve\ntimestep 0.005\n"
          "neigh_modify every 1 delay 0 check no\nrun 7\n");
  HSLocalForces lf(h.lmp, "test");
  lf.init();
  check_c(h, lf, random_c(h.lmp, 20, 3, true), "after run 7");
  h.lines("run 5\n");
  check_c(h, lf, random_c(h.lmp, 20, 4, true), "after run 5 more");
}

// HSLocalForces::bonded_term(): one term by its style's compute() on a
// list of that term alone (pcva's local projection, hs_local_modified.cpp).
// A 4-atom molecule whose only interaction is one dihedral charmm term with
// weight 1: its 1-4 pair energy goes through the pair style's ev_tally(),
// which follows the pair style's own flags (those of its last compute()).
// Expected: LAMMPS' own potential energy and forces of a full evaluation
// (pe = the dihedral's energy + the 1-4 part), also after the pair style's
// flags were left without energy, as a step without thermo leaves them;
// LAMMPS' state (tallies, flags, atom->x, atom->f) as before
TEST(LocalForces, BondedTermIsItsStylesEnergyAndForce)
{
  HSLammps h;
  h.lines(R"LMP(units lj
atom_style full
atom_modify map array
boundary p p p
region box block -6 6 -6 6 -6 6
create_box 1 box bond/types 1 dihedral/types 1 extra/bond/per/atom 2 extra/dihedral/per/atom 1 extra/special/per/atom 6
create_atoms 1 single 0.0 0.0 0.0
create_atoms 1 single 1.1 0.1 0.0
create_atoms 1 single 1.6 1.1 0.1
create_atoms 1 single 2.9 1.3 0.8
set atom 1 charge 0.3
set atom 4 charge -0.4
mass 1 1.0
pair_style lj/charmm/coul/charmm 4.0 5.0
pair_coeff 1 1 1.0 0.9 0.7 0.8
bond_style zero
bond_coeff 1 1.1
dihedral_style charmm
dihedral_coeff 1 1.2 3 0 1.0
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
create_bonds single/dihedral 1 1 2 3 4
special_bonds charmm
thermo_style custom step pe
thermo_modify norm no
run 0
)LMP");
  auto *lmp = h.lmp;
  const double pe = lammps_get_thermo(lmp, "pe");
  LAMMPS_NS::Force *force = lmp->force;
  LAMMPS_NS::Atom *atom = lmp->atom;
  ASSERT_EQ(lmp->neighbor->ndihedrallist, 1);
  int row[4];
  for (int k = 0; k < 4; k++) row[k] = lmp->neighbor->dihedrallist[0][k];
  const int type = lmp->neighbor->dihedrallist[0][4];
  // the 1-4 part alone, from the pair style's single() with its 1-4 table
  // absent (special_bonds charmm: the pair list has no 1-4 pair): pe less
  // the dihedral's own tally
  const double e14 = pe - force->dihedral->energy;
  EXPECT_GT(std::fabs(e14), 1e-3) << "the test needs a 1-4 part";
  const int n = atom->nlocal + atom->nghost;
  std::vector<double> fb(3 * n, 0.0);
  std::vector<double *> f(n);
  for (int i = 0; i < n; i++) f[i] = &fb[3 * i];
  HSLocalForces lf(lmp, "test");
  lf.init();
  for (int flags = 0; flags < 2; flags++) {
    // flags 1: the pair style's flags as a step without energy leaves them
    if (flags) force->pair->eflag_either = force->pair->eflag_global = 0;
    const int ef[2] = {force->pair->eflag_either, force->pair->eflag_global};
    const double tally[3] = {force->pair->eng_vdwl, force->pair->eng_coul,
                             force->dihedral->energy};
    double **x0 = atom->x, **f0 = atom->f;
    std::fill(fb.begin(), fb.end(), 0.0);
    const double e = lf.bonded_term(2, row, type, atom->x, f.data());
    EXPECT_NEAR(e, pe, 1e-12 * std::fabs(pe)) << "pair flags " << (flags ? "off" : "as run 0 left them");
    // forces: LAMMPS' own of run 0 (the dihedral's and the 1-4 pair's only),
    // each atom's image folded into it
    for (int k = 0; k < 4; k++) {
      const int o = atom->map(atom->tag[row[k]]);
      for (int d = 0; d < 3; d++)
        EXPECT_NEAR(f[row[k]][d], atom->f[o][d], 1e-12) << "atom " << atom->tag[row[k]];
    }
    EXPECT_EQ(atom->x, x0);
    EXPECT_EQ(atom->f, f0);
    EXPECT_EQ(force->pair->eflag_either, ef[0]);
    EXPECT_EQ(force->pair->eflag_global, ef[1]);
    EXPECT_EQ(force->pair->eng_vdwl, tally[0]);
    EXPECT_EQ(force->pair->eng_coul, tally[1]);
    EXPECT_EQ(force->dihedral->energy, tally[2]);
  }
}

TEST(LocalForces, ReportsUnrestrictableStyles)
{
  {
    HSLammps h;
    h.lines("units lj\natom_style charge\natom_modify map array\nregion box block 0 6 0 6 0 6\n"
            "create_box 1 box\ncreate_atoms 1 random 20 5 NULL\nmass 1 1.0\nset group all charge 0.1\n"
            "pair_style lj/cut/coul/long 2.5\npair_coeff 1 1 1.0 1.0\nkspace_style ewald 1e-4\n");
    HSLocalForces lf(h.lmp, "test");
    h.lines("run 0\n");
    lf.init();
    // kspace is no term of V_C: the real-space pair style restricts
    // exactly, and the engine holds the reciprocal part (LocalEngine.
    // KspaceHeld...)
    EXPECT_TRUE(lf.exact()) << lf.unrestrictable();
  }
  {
    HSLammps h;
    // a LAMMPS built without MANYBODY (the stock 4Feb2025 build of the tests)
    // has no many-body pair style to try
    if (lammps_has_style(h.lmp, "pair", "tersoff")) {
      h.lines("units metal\natom_style atomic\natom_modify map array\nlattice fcc 4.05\n"
              "region box block 0 3 0 3 0 3\ncreate_box 1 box\ncreate_atoms 1 box\nmass 1 27.0\n"
              "pair_style tersoff\n");
      // tersoff needs a potential file; its manybody flag is set at construction
      HSLocalForces lf(h.lmp, "test");
      lf.init();
      EXPECT_FALSE(lf.exact());
      EXPECT_NE(lf.unrestrictable().find("many-body"), std::string::npos) << lf.unrestrictable();
    } else
      printf("pair style tersoff is not in this LAMMPS (MANYBODY package): many-body case "
             "not tried\n");
  }
  {
    HSLammps h;
    h.lines("units lj\natom_style atomic\natom_modify map array\nregion box block 0 6 0 6 0 6\n"
            "create_box 2 box\ncreate_atoms 1 random 20 5 NULL\nmass * 1.0\n"
            "pair_style hybrid lj/cut 2.5 soft 1.0\npair_coeff 1 1 lj/cut 1.0 1.0\n"
            "pair_coeff 1 2 soft 1.0\npair_coeff 2 2 soft 1.0\n");
    HSLocalForces lf(h.lmp, "test");
    lf.init();
    // pair-wise sub-styles: restricted (LocalForcesHybrid below)
    EXPECT_TRUE(lf.exact()) << lf.unrestrictable();
    // a many-body sub-style makes hybrid many-body (PairHybrid::flags())
    if (lammps_has_style(h.lmp, "pair", "tersoff")) {
      h.lines("pair_style hybrid lj/cut 2.5 tersoff\n");
      lf.init();
      EXPECT_FALSE(lf.exact());
      EXPECT_NE(lf.unrestrictable().find("many-body"), std::string::npos) << lf.unrestrictable();
    }
  }
  {
    // bonded hybrid styles split LAMMPS' list among their sub-styles only at
    // a list build: a restricted list is not seen in other steps (before:
    // cva and pcva local computed every angle's forces at each contact and
    // lost energy; sweep of 2026-12-01)
    HSLammps h;
    h.lines("units lj\natom_style angle\natom_modify map array\nregion box block 0 6 0 6 0 6\n"
            "create_box 1 box angle/types 2\ncreate_atoms 1 random 20 5 NULL\nmass 1 1.0\n"
            "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n"
            "angle_style hybrid harmonic cosine\nangle_coeff 1 harmonic 5.0 110.0\n"
            "angle_coeff 2 cosine 1.0\n");
    HSLocalForces lf(h.lmp, "test");
    lf.init();
    EXPECT_FALSE(lf.exact());
    EXPECT_NE(lf.unrestrictable().find("angle style hybrid"), std::string::npos)
        << lf.unrestrictable();
    EXPECT_EQ(lf.unrestrictable().find("pair style"), std::string::npos) << lf.unrestrictable();
  }
}

// ---- rank-local rows (compute_rows(), issue 20): C may hold any local
// copies, owned or ghost; no communication. Checked against LAMMPS' full
// forces gathered by tag (members) and against a brute-force V_C over the
// gathered positions (partners), on every rank count, and on one rank
// against compute() (the pair list restriction), with labels, after atoms
// moved (recompute(), snapshots) and with bonded terms and special pairs.

namespace {

// per tag (0-based), gathered on every rank: positions and full forces
void gather_by_tag(LAMMPS_NS::LAMMPS *lmp, std::vector<double> &x, std::vector<double> &f)
{
  auto *atom = lmp->atom;
  const int n = (int) atom->natoms;
  std::vector<double> xl(3 * n, 0.0), fl(3 * n, 0.0);
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 3; k++) {
      xl[3 * (atom->tag[i] - 1) + k] = atom->x[i][k];
      fl[3 * (atom->tag[i] - 1) + k] = atom->f[i][k];
    }
  x.assign(3 * n, 0.0);
  f.assign(3 * n, 0.0);
  MPI_Allreduce(xl.data(), x.data(), 3 * n, MPI_DOUBLE, MPI_SUM, lmp->world);
  MPI_Allreduce(fl.data(), f.data(), 3 * n, MPI_DOUBLE, MPI_SUM, lmp->world);
}

// -grad V_C over the gathered positions (by tag), C by tag
std::vector<double> brute_lj_tags(LAMMPS_NS::LAMMPS *lmp, const std::vector<double> &x,
                                  const std::set<int> &ctags)
{
  return brute_lj_points(lmp, x.data(), (int) lmp->atom->natoms,
                         [&](int i) { return ctags.count(i + 1) > 0; });
}

// how far local copy j lies outside this rank's sub-domain
double outside(LAMMPS_NS::LAMMPS *lmp, int j)
{
  auto *domain = lmp->domain;
  double d2 = 0.0;
  for (int k = 0; k < 3; k++) {
    const double x = lmp->atom->x[j][k];
    const double e = std::max({0.0, domain->sublo[k] - x, x - domain->subhi[k]});
    d2 += e * e;
  }
  return std::sqrt(d2);
}

// a random C of n local copies, one per tag, ghosts included where all
// their neighbours within the neighbor cutoff are local copies too
std::vector<int> random_copies(LAMMPS_NS::LAMMPS *lmp, int n, unsigned seed)
{
  auto *atom = lmp->atom;
  const double reach = lmp->comm->get_comm_cutoff() - lmp->neighbor->cutneighmax;
  std::mt19937 rng(seed);
  std::vector<int> all(atom->nlocal + atom->nghost);
  for (size_t i = 0; i < all.size(); i++) all[i] = (int) i;
  std::shuffle(all.begin(), all.end(), rng);
  std::set<int> tags;
  std::vector<int> c;
  for (int j : all) {
    if ((int) c.size() >= n) break;
    if (j >= atom->nlocal && outside(lmp, j) > reach) continue;
    if (!tags.insert((int) atom->tag[j]).second) continue;
    c.push_back(j);
  }
  return c;
}

// the positions of all local atoms now (right after a run 0: those of the
// list build), for HSLocalForces::set_reference()
struct Reference {
  std::vector<double> buf;
  std::vector<double *> rows;
  explicit Reference(LAMMPS_NS::LAMMPS *lmp)
  {
    auto *atom = lmp->atom;
    const int nall = atom->nlocal + atom->nghost;
    buf.assign(&atom->x[0][0], &atom->x[0][0] + 3 * nall);
    for (int i = 0; i < nall; i++) rows.push_back(buf.data() + 3 * i);
  }
  double **get() { return rows.data(); }
};

}    // namespace

// (newton_pair off too: the styles then leave a ghost's force out of a pair
// term, and the rows, which list each term once, evaluate with newton_pair
// on; without that the partners that are ghosts lost their part)
TEST(LocalForcesRows, GhostCopiesOnAnyRankCount)
{
  for (bool newton : {true, false}) {
    HSLammps h;
    std::string in = fluid_input(newton);
    in.insert(in.find("run 0"), "comm_modify cutoff 5.5\n");
    h.lines(in);
    auto *atom = h.lmp->atom;
    HSLocalForces lf(h.lmp, "test");
    lf.init();
    ASSERT_EQ(lf.rows_unsupported(), "");
    Reference ref(h.lmp);
    lf.set_reference(ref.get());
    std::vector<double> X, F;
    gather_by_tag(h.lmp, X, F);
    double fscale = 0.0;
    for (double v : F) fscale = std::max(fscale, std::fabs(v));
    int nghost_members = 0, cases = 0;
    // (a C of 200: the search for pairs of two members jumps by bisection
    // there, and walks for the small C of a cluster)
    for (int n : {1, 2, 4, 8, 40, 200})
      for (unsigned seed = 1; seed <= 6; seed++) {
        const auto c = random_copies(h.lmp, n, 1000u * seed + n + 17u * h.lmp->comm->me);
        if (c.empty()) continue;
        ++cases;
        const Snapshot before = snap(h.lmp);
        lf.compute_rows(c.data(), (int) c.size());
        expect_unchanged(h.lmp, before, "rows");
        std::set<int> ctags;
        for (int j : c) {
          ctags.insert((int) atom->tag[j]);
          if (j >= atom->nlocal) ++nghost_members;
        }
        const auto ref = brute_lj_tags(h.lmp, X, ctags);
        double **fl = lf.forces();
        std::set<int> seen;
        for (int j : lf.touched()) {
          const int t = (int) atom->tag[j];
          EXPECT_TRUE(seen.insert(t).second) << "tag " << t << " reported twice";
          for (int k = 0; k < 3; k++) {
            // members: the full force; partners: V_C's part of theirs
            const double want = ctags.count(t) ? F[3 * (t - 1) + k] : ref[3 * (t - 1) + k];
            EXPECT_NEAR(fl[j][k], want, 1e-12 * fscale)
                  << "newton " << newton << " |C| " << c.size() << " tag " << t
                << (j >= atom->nlocal ? " (ghost)" : "")
                << (ctags.count(t) ? " member" : " partner") << " dim " << k;
          }
        }
        for (int j : c) EXPECT_TRUE(seen.count((int) atom->tag[j])) << "member not reported";
        for (int t = 1; t <= (int) atom->natoms; t++)
          if (!seen.count(t))
            for (int k = 0; k < 3; k++)
              EXPECT_EQ(ref[3 * (t - 1) + k], 0.0) << "partner tag " << t << " missing";
      }
    EXPECT_GE(cases, 25);
    int g = 0;
    MPI_Allreduce(&nghost_members, &g, 1, MPI_INT, MPI_SUM, h.lmp->world);
    EXPECT_GT(g, 20) << "too few ghost members tried";
  }
}

// the same touched copies and forces (to 1e-13 of the largest) from two
// restricted evaluations: b's rows against a's list restriction
static void expect_same_forces(HSLocalForces &a, HSLocalForces &b,
                               const LAMMPS_NS::tagint *tag, const std::string &what)
{
  double **fa = a.forces(), **fb = b.forces();
  // (the same copies, each once: rows list them in the order they reach
  // them, the list restriction in index order)
  std::vector<int> ta(a.touched()), tb(b.touched());
  std::sort(ta.begin(), ta.end());
  std::sort(tb.begin(), tb.end());
  ASSERT_EQ(ta, tb) << what;
  ASSERT_TRUE(std::adjacent_find(tb.begin(), tb.end()) == tb.end()) << what << ": a copy twice";
  double scale = 1.0;
  for (int i : a.touched())
    for (int k = 0; k < 3; k++) scale = std::max(scale, std::fabs(fa[i][k]));
  for (int i : a.touched())
    for (int k = 0; k < 3; k++)
      EXPECT_NEAR(fb[i][k], fa[i][k], 1e-13 * scale) << what << " tag " << tag[i];
}

// one rank: compute_rows() of the owned copies equals compute() (touched
// atoms and forces), with labels (NORMAL and CROSS), after atoms moved
// (recompute() and a snapshot), in the fluid and in the melt
TEST(LocalForcesRows, SameAsListRestrictionOnOneRank)
{
  const std::string data = melt_data(scratch_name("melt_rows.data"));
  for (bool melt : {false, true}) {
    HSLammps h;
    h.lines(melt ? melt_input(data, true) : fluid_input(true));
    if (h.lmp->comm->nprocs > 1) GTEST_SKIP() << "compute() is a collective on several ranks";
    auto *atom = h.lmp->atom;
    HSLocalForces a(h.lmp, "test"), b(h.lmp, "test");
    a.init();
    b.init();
    ASSERT_EQ(b.rows_unsupported(), "");
    Reference ref(h.lmp);
    b.set_reference(ref.get());
    const int nall = atom->nlocal + atom->nghost;
    std::vector<int> lab(nall, -1);
    auto compare = [&](const std::vector<int> &, const std::string &what) {
      expect_same_forces(a, b, atom->tag, what);
    };
    for (int n : {1, 3, 20, atom->nlocal})
      for (unsigned seed = 1; seed <= 3; seed++)
        for (int mode = 0; mode < 3; mode++) {
          const auto c = random_c(h.lmp, n, seed * 13 + n, seed == 2);
          // labels: none, or the atoms of C in two groups (cross terms)
          std::fill(lab.begin(), lab.end(), -1);
          if (mode > 0)
            for (size_t k = 0; k < c.size(); k++)
              for (int j = c[k]; j >= 0; j = atom->sametag[j]) lab[j] = (int) (k % 2);
          const auto m = mode == 2 ? HSLocalForces::CROSS : HSLocalForces::NORMAL;
          a.set_labels(mode ? lab.data() : nullptr, m);
          b.set_labels(mode ? lab.data() : nullptr, m);
          const std::string what = std::string(melt ? "melt" : "fluid") + " |C| " +
              std::to_string(c.size()) + " mode " + std::to_string(mode);
          a.compute(c.data(), (int) c.size(), false);
          b.compute_rows(c.data(), (int) c.size());
          compare(c, what);
        }
    // after a move of C (no list build): recompute() and a snapshot
    a.set_labels(nullptr);
    b.set_labels(nullptr);
    const auto c = random_c(h.lmp, 10, 99, true);
    a.compute(c.data(), (int) c.size(), false);
    b.compute_rows(c.data(), (int) c.size());
    HSLocalForces::Snapshot sb;
    b.save(sb);
    std::vector<std::array<double, 3>> saved(c.size());
    for (size_t k = 0; k < c.size(); k++)
      for (int d = 0; d < 3; d++) {
        saved[k][d] = atom->x[c[k]][d];
        const double dx = 0.03 * (d + 1) * ((k % 2) ? 1 : -1);
        for (int j = c[k]; j >= 0; j = atom->sametag[j]) atom->x[j][d] += dx;
      }
    a.recompute();
    b.recompute();
    compare(c, "recompute after a move");
    const auto other = random_c(h.lmp, 5, 7, false);
    b.compute_rows(other.data(), (int) other.size());
    b.recompute(sb);
    compare(c, "snapshot after a move");
    for (size_t k = 0; k < c.size(); k++)
      for (int d = 0; d < 3; d++) {
        const double dx = saved[k][d] - atom->x[c[k]][d];
        for (int j = c[k]; j >= 0; j = atom->sametag[j]) atom->x[j][d] += dx;
      }
  }
  remove(data.c_str());
}

// neigh_modify exclude (by type, by a pair of groups, by molecule within a
// group, intra and inter): compute_rows() leaves out the pairs LAMMPS' own
// list build leaves out, so it equals compute() on LAMMPS' restricted
// list, and the exclusion changed the forces (it took pairs off). One
// rank: compute() is a collective on several (test_mpi_local.sh runs the
// engine with an exclusion on 1, 2 and 4 ranks)
TEST(LocalForcesRows, ExclusionsAsLAMMPSListBuild)
{
  const std::string data = melt_data(scratch_name("melt_excl.data"));
  struct Case {
    bool melt;
    std::string setup, exclude;
  };
  const std::string two_types = "group ga id <= 100\ngroup gb id > 60\n";
  const std::vector<Case> cases = {
      {false, two_types, "neigh_modify exclude type 1 2"},
      {false, two_types, "neigh_modify exclude group ga gb"},
      {false, two_types, "neigh_modify exclude type 2 2 exclude group gb ga"},
      {true, "group half id <= 500\n", "neigh_modify exclude molecule/intra half"},
      {true, "group half id <= 500\n", "neigh_modify exclude molecule/inter half"},
  };
  for (const Case &k : cases) {
    HSLammps h;
    std::string in = k.melt ? melt_input(data, true) : fluid_input(true);
    if (!k.melt) {    // a second type on 40 % of the atoms
      in.replace(in.find("create_box 1 box"), 16, "create_box 2 box");
      in.replace(in.find("mass 1 1.0"), 10, "mass * 1.0\nset type 1 type/fraction 2 0.4 99");
      in.replace(in.find("pair_coeff 1 1"), 14, "pair_coeff * *");
    }
    in.insert(in.find("run 0"), k.setup);
    h.lines(in);
    if (h.lmp->comm->nprocs > 1) GTEST_SKIP() << "compute() is a collective on several ranks";
    auto *atom = h.lmp->atom;
    const auto all = random_c(h.lmp, atom->nlocal, 3, false);
    // without the exclusion first, then with it
    std::vector<double> before;
    for (int with = 0; with < 2; with++) {
      if (with) h.lines(k.exclude + "\nrun 0\n");
      HSLocalForces a(h.lmp, "test"), b(h.lmp, "test");
      a.init();
      b.init();
      ASSERT_EQ(b.rows_unsupported(), "") << k.exclude;
      Reference ref(h.lmp);
      b.set_reference(ref.get());
      for (int n : {1, 3, 20, atom->nlocal})
        for (unsigned seed = 1; seed <= 3; seed++) {
          const auto c = random_c(h.lmp, n, seed * 7 + n, seed == 2);
          const std::string what = k.exclude + (with ? "" : " (not yet)") + " |C| " +
              std::to_string(c.size()) + " seed " + std::to_string(seed);
          a.compute(c.data(), (int) c.size(), false);
          b.compute_rows(c.data(), (int) c.size());
          expect_same_forces(a, b, atom->tag, what);
        }
      // every atom in C: the exclusion must have changed forces
      b.compute_rows(all.data(), (int) all.size());
      std::vector<double> now(3 * atom->nlocal);
      for (int i = 0; i < atom->nlocal; i++)
        for (int d = 0; d < 3; d++) now[3 * i + d] = b.forces()[i][d];
      if (!with) before = now;
      else {
        double diff = 0.0;
        for (size_t m = 0; m < now.size(); m++) diff = std::max(diff, std::fabs(now[m] - before[m]));
        EXPECT_GT(diff, 1e-3) << k.exclude << ": took no pair off";
      }
    }
  }
  remove(data.c_str());
}

// lj/cut's kernel (hs_ljcut.h) in the restricted evaluations: the same
// forces, bit for bit, as the style's compute() on the same restricted
// lists (fluid; melt with special_bonds lj 0 1 1), in compute_rows() and in
// recompute() after a move; the table built here as PairLJCut::init_one()
// builds its lj1 and lj2. A wrong table (lj1 one part in 1e12 off) is
// refused at the first evaluation, whose forces are then compute()'s
// lj/cut's kernel table of the input's coefficients, written here from
// epsilon and sigma (as PairLJCut::init_one() builds lj1..lj4 and the
// offset); wrong: two of them off by 1e-12 (the kernel must be refused).
// coef holds the table; t.coef null if the style has no epsilon or sigma
HardSphere::LJCutTable lj_table(LAMMPS_NS::LAMMPS *lmp, std::vector<double> &coef, bool wrong)
{
  auto *pair = lmp->force->pair;
  const int nt = lmp->atom->ntypes, ntp1 = nt + 1;
  int dim = 0;
  auto **eps = (double **) pair->extract("epsilon", dim);
  auto **sig = (double **) pair->extract("sigma", dim);
  HardSphere::LJCutTable t;
  if (!eps || !sig) return t;
  coef.assign(7 * ntp1 * ntp1, 0.0);
  for (int it = 1; it <= nt; it++)
    for (int jt = 1; jt <= nt; jt++) {
      const int lo = std::min(it, jt), hi = std::max(it, jt);
      coef[7 * (it * ntp1 + jt)] = 48.0 * eps[lo][hi] * pow(sig[lo][hi], 12.0);
      coef[7 * (it * ntp1 + jt) + 1] = 24.0 * eps[lo][hi] * pow(sig[lo][hi], 6.0);
      // (energy: the inputs have pair_modify shift yes, as init_one() builds it)
      coef[7 * (it * ntp1 + jt) + 2] = 4.0 * eps[lo][hi] * pow(sig[lo][hi], 12.0);
      coef[7 * (it * ntp1 + jt) + 3] = 4.0 * eps[lo][hi] * pow(sig[lo][hi], 6.0);
      const double ratio = sig[lo][hi] / sqrt(pair->cutsq[lo][hi]);
      coef[7 * (it * ntp1 + jt) + 4] = 4.0 * eps[lo][hi] * (pow(ratio, 12.0) - pow(ratio, 6.0));
      if (wrong) {
        coef[7 * (it * ntp1 + jt)] *= 1.0 + 1e-12;
        coef[7 * (it * ntp1 + jt) + 4] *= 1.0 + 1e-12;
      }
    }
  t.coef = coef.data();
  t.stride = 7;
  t.ntp1 = ntp1;
  return t;
}

TEST(LocalForcesRows, LJKernelSameBitsAsCompute)
{
  const std::string data = melt_data(scratch_name("melt_ljk.data"));
  for (bool melt : {false, true})
    for (bool wrong : {false, true}) {
      HSLammps h;
      h.lines(melt ? melt_input(data, true) : fluid_input(true));
      auto *atom = h.lmp->atom;
      std::vector<double> coef;
      const HardSphere::LJCutTable t = lj_table(h.lmp, coef, wrong);
      ASSERT_TRUE(t.coef);
      HSLocalForces a(h.lmp, "test"), b(h.lmp, "test");
      a.init();
      b.init();
      b.set_lj_table(t);
      EXPECT_EQ(a.lj_kernel(), -1);
      Reference ref(h.lmp);
      a.set_reference(ref.get());
      b.set_reference(ref.get());
      auto same = [&](const std::string &what) {
        ASSERT_EQ(a.touched(), b.touched()) << what;
        double **fa = a.forces(), **fb = b.forces();
        int nonzero = 0;
        for (int i : a.touched()) {
          ASSERT_EQ(0, memcmp(fa[i], fb[i], 3 * sizeof(double)))
              << what << " tag " << atom->tag[i] << ": " << fa[i][0] << " vs " << fb[i][0];
          nonzero += fa[i][0] != 0.0;
        }
        EXPECT_GT(nonzero, 0) << what;
      };
      const std::string sys = std::string(melt ? "melt" : "fluid") + (wrong ? " wrong" : "");
      for (int n : {1, 3, 20})
        for (unsigned seed = 1; seed <= 3; seed++) {
          const auto c = random_c(h.lmp, n, seed * 17 + n, seed == 2);
          a.compute_rows(c.data(), (int) c.size());
          b.compute_rows(c.data(), (int) c.size());
          same(sys + " |C| " + std::to_string(n));
          EXPECT_EQ(b.lj_kernel(), wrong ? 0 : 1) << sys;
        }
      const auto c = random_c(h.lmp, 10, 5, true);
      a.compute_rows(c.data(), (int) c.size());
      b.compute_rows(c.data(), (int) c.size());
      for (size_t k = 0; k < c.size(); k++)
        for (int d = 0; d < 3; d++)
          for (int j = c[k]; j >= 0; j = atom->sametag[j]) atom->x[j][d] += 0.02 * (d + 1);
      a.recompute();
      b.recompute();
      same(sys + " recompute after a move");
      for (size_t k = 0; k < c.size(); k++)
        for (int d = 0; d < 3; d++)
          for (int j = c[k]; j >= 0; j = atom->sametag[j]) atom->x[j][d] -= 0.02 * (d + 1);
      // with the energy (vci's evaluations): forces and V_C to the bit, the
      // energy kernel checked on its own
      EXPECT_EQ(b.lj_energy_kernel(), -1) << sys;
      a.keep_energy(true);
      b.keep_energy(true);
      for (int n : {1, 4, 20})
        for (unsigned seed = 1; seed <= 2; seed++) {
          const auto ce = random_c(h.lmp, n, seed * 29 + n, seed == 2);
          a.compute_rows(ce.data(), (int) ce.size());
          b.compute_rows(ce.data(), (int) ce.size());
          const std::string what = sys + " with energy, |C| " + std::to_string(n);
          same(what);
          const double ea = a.energy(), eb = b.energy();
          EXPECT_NE(ea, 0.0) << what;
          EXPECT_EQ(0, memcmp(&ea, &eb, sizeof(double))) << what << ": " << ea << " vs " << eb;
          EXPECT_EQ(b.lj_energy_kernel(), wrong ? 0 : 1) << what;
          a.recompute();
          b.recompute();
          same(what + " recompute");
          const double ra = a.energy(), rb = b.energy();
          EXPECT_EQ(0, memcmp(&ra, &rb, sizeof(double))) << what << " recompute";
        }
    }
  remove(data.c_str());
}

// cross_rows(): the cross terms of C straight from its rows are what
// compute_rows() gives C's copies in mode CROSS, to the bit (forces, and
// the energy with keep_energy()), the other clusters' labels those of the
// atoms it touched; where lj/cut's kernel is not in use it does nothing and
// says so. C (label 0) among atoms of two other clusters (labels 1, 2)
// and unlabelled ones, in the fluid and the melt (special bonds)
TEST(LocalForcesRows, CrossRowsSameBitsAsCrossEvaluation)
{
  const std::string data = melt_data(scratch_name("melt_cross.data"));
  for (bool melt : {false, true}) {
    HSLammps h;
    h.lines(melt ? melt_input(data, true) : fluid_input(true));
    auto *atom = h.lmp->atom;
    std::vector<double> coef;
    const HardSphere::LJCutTable t = lj_table(h.lmp, coef, false);
    ASSERT_TRUE(t.coef);
    HSLocalForces plain(h.lmp, "test"), b(h.lmp, "test");
    plain.init();
    b.init();
    b.set_lj_table(t);
    Reference ref(h.lmp);
    plain.set_reference(ref.get());
    b.set_reference(ref.get());
    const int nall = atom->nlocal + atom->nghost;
    std::vector<int> lab(nall, -1);
    int nonzero = 0, others_seen = 0;
    for (bool energy : {false, true}) {
      b.keep_energy(energy);
      for (int n : {1, 2, 8})
        for (unsigned seed = 1; seed <= 4; seed++) {
          const std::string what = std::string(melt ? "melt" : "fluid") + " |C| " +
              std::to_string(n) + " seed " + std::to_string(seed) + (energy ? " energy" : "");
          // C, then 200 atoms of the others (all of an atom's copies labelled)
          auto pool = random_c(h.lmp, n + 200, seed * 7 + n, seed == 2);
          const std::vector<int> c(pool.begin(), pool.begin() + n);
          std::fill(lab.begin(), lab.end(), -1);
          for (size_t k = 0; k < pool.size(); k++)
            for (int j = pool[k]; j >= 0; j = atom->sametag[j])
              lab[j] = (int) k < n ? 0 : 1 + (int) (k % 2);
          // the kernel verified on a first evaluation with forces
          b.set_labels(nullptr);
          b.compute_rows(c.data(), n);
          ASSERT_EQ(b.lj_kernel(), 1) << what;
          b.set_labels(lab.data(), HSLocalForces::CROSS);
          b.compute_rows(c.data(), n);
          if (energy) ASSERT_EQ(b.lj_energy_kernel(), 1) << what;
          std::vector<std::array<double, 3>> want(n);
          double **fb = b.forces();
          for (int k = 0; k < n; k++) want[k] = {fb[c[k]][0], fb[c[k]][1], fb[c[k]][2]};
          std::set<int> want_labels;
          for (int j : b.touched())
            if (lab[j] > 0) want_labels.insert(lab[j]);
          const double want_e = b.energy();
          std::vector<std::array<double, 3>> got(n, {-1.0, -1.0, -1.0});
          std::vector<int> labels;
          ASSERT_TRUE(b.cross_rows(c.data(), n, reinterpret_cast<double(*)[3]>(got.data()),
                                   labels))
              << what;
          for (int k = 0; k < n; k++) {
            EXPECT_EQ(0, memcmp(want[k].data(), got[k].data(), 3 * sizeof(double)))
                << what << " tag " << atom->tag[c[k]] << ": " << want[k][0] << " vs "
                << got[k][0];
            nonzero += got[k][0] != 0.0;
          }
          EXPECT_EQ(std::set<int>(labels.begin(), labels.end()), want_labels) << what;
          others_seen += (int) want_labels.size();
          if (energy) {
            const double e = b.energy();
            EXPECT_EQ(0, memcmp(&e, &want_e, sizeof(double))) << what << ": " << e << " vs "
                                                               << want_e;
          }
          // without the kernel: nothing done
          plain.set_labels(lab.data(), HSLocalForces::CROSS);
          plain.compute_rows(c.data(), n);
          labels.clear();
          EXPECT_FALSE(plain.cross_rows(c.data(), n, reinterpret_cast<double(*)[3]>(got.data()),
                                        labels))
              << what;
          EXPECT_TRUE(labels.empty()) << what;
        }
    }
    // the cases had cross terms, in force and in neighbours
    EXPECT_GT(nonzero, 10);
    EXPECT_GT(others_seen, 10);
  }
  remove(data.c_str());
}

// rows_unsupported(): newton_pair off is no reason any more (it was before
// 30 Nov 2026; GhostCopiesOnAnyRankCount checks the forces with it)
TEST(LocalForcesRows, NewtonPairOffSupported)
{
  HSLammps h;
  h.lines(fluid_input(false));
  HSLocalForces lf(h.lmp, "test");
  lf.init();
  EXPECT_EQ(lf.rows_unsupported(), "");
}

// set_near(): a row's scan also lists its contact neighbours (the local
// engine's crow()): against a brute-force search over all local copies at
// the reference positions, in (ID, index) order, with a group that leaves
// atoms out and, on the melt, the bonded partners special_bonds lj 0.0
// leaves out of the rows (they must be listed: they can touch)
TEST(LocalForcesRows, NearRowsAreTheContactNeighbours)
{
  int nprocs = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  for (bool melt : {false, true}) {
    // the melt on one rank: a ghost's special list is not known without a
    // topology, so the rows of a molecular system on several ranks need one
    if (melt && nprocs > 1) continue;
    const std::string data = melt ? melt_data(scratch_name("melt-near.data")) : "";
    HSLammps h;
    if (melt) {
      h.lines(melt_input(data, true));
      remove(data.c_str());
    } else {
      std::string in = fluid_input(true);
      in.insert(in.find("run 0"), "comm_modify cutoff 5.5\n");
      h.lines(in);
    }
    h.lines("group g id <= 130\n");
    auto *atom = h.lmp->atom;
    const int gbit = 1 << h.lmp->group->find("g");
    const double cut = 1.5;
    ASSERT_LT(cut, h.lmp->neighbor->cutneighmax);
    HSLocalForces lf(h.lmp, "test");
    lf.init();
    ASSERT_EQ(lf.rows_unsupported(), "");
    lf.set_near(cut, gbit);
    Reference ref(h.lmp);
    lf.set_reference(ref.get());
    double **xr = ref.get();
    const int nall = atom->nlocal + atom->nghost;
    // melt: owned copies (the same reason); fluid: any copies
    std::vector<int> c;
    if (melt)
      c = random_c(h.lmp, 60, 11, true);
    else
      c = random_copies(h.lmp, 60, 23u + 7u * h.lmp->comm->me);
    ASSERT_FALSE(c.empty());
    int n0;
    EXPECT_EQ(lf.near_row(c[0], n0), nullptr) << "a row listed before its scan";
    lf.compute_rows(c.data(), (int) c.size());
    std::set<int> in_c(c.begin(), c.end());
    int listed = 0, excluded_listed = 0, left_out = 0;
    for (int a : c) {
      int n = -1;
      const int *got = lf.near_row(a, n);
      ASSERT_NE(got, nullptr) << "no contact neighbours for copy " << a;
      std::vector<std::pair<int, int>> want;
      for (int j = 0; j < nall; j++) {
        if (j == a || atom->tag[j] == atom->tag[a]) continue;
        double r2 = 0.0;
        for (int k = 0; k < 3; k++) r2 += (xr[a][k] - xr[j][k]) * (xr[a][k] - xr[j][k]);
        if (r2 > cut * cut) continue;
        if (!(atom->mask[j] & gbit)) {
          ++left_out;
          continue;
        }
        want.emplace_back((int) atom->tag[j], j);
      }
      std::sort(want.begin(), want.end());
      ASSERT_EQ(n, (int) want.size()) << "copy " << a << " tag " << atom->tag[a];
      for (int k = 0; k < n; k++) EXPECT_EQ(got[k], want[k].second) << "entry " << k;
      listed += n;
      if (melt && atom->molecular) {
        const int o = atom->map(atom->tag[a]);
        for (int k = 0; k < n; k++)
          for (int m = 0; m < atom->nspecial[o][0]; m++)
            if (atom->special[o][m] == atom->tag[got[k]]) ++excluded_listed;
      }
    }
    // (summed over the ranks)
    int mine[2] = {listed, left_out}, all[2];
    MPI_Allreduce(mine, all, 2, MPI_INT, MPI_SUM, h.lmp->world);
    EXPECT_GT(all[0], 50);
    EXPECT_GT(all[1], 10) << "the group test was not tried";
    if (melt) EXPECT_GT(excluded_listed, 10) << "no bonded partner (left out of the rows) tried";
    // a copy without a row has none
    for (int j = 0; j < atom->nlocal; j++)
      if (!in_c.count(j)) {
        int n;
        EXPECT_EQ(lf.near_row(j, n), nullptr);
        break;
      }
  }
}

// ---- pair hybrid: the restricted rows split among the sub-styles' own
// lists by the type skips LAMMPS built them with. Two types: hybrid with
// lj/cut on 1-1, soft on 1-2 and none on 2-2; hybrid/overlay with lj/cut
// on every pair and soft added on 1-1. Members against LAMMPS' full force,
// partners against a brute-force sum of the two potentials written here
// (itself checked against LAMMPS' full forces), on any rank count; both
// restrictions (rows, and compute() on the list of all pairs); the terms
// recorded for pcva's projection never hold a pair no sub-style computes
// (single() would stop on it); LAMMPS' state, the sub-styles' tallies
// included, unchanged.

namespace {

const double SOFT_A = 3.0, SOFT_RC = 2.0;

std::string hybrid_input(bool overlay)
{
  std::string in = "units lj\natom_style atomic\natom_modify map array\nboundary p p p\n"
                   "newton on\nlattice fcc 0.5729578\nregion box block 0 4 0 4 0 4\n"
                   "create_box 2 box\ncreate_atoms 1 box\nmass * 1.0\n"
                   "set type 1 type/fraction 2 0.5 8191\n"
                   "displace_atoms all random 0.15 0.15 0.15 4711 units box\n";
  const std::string soft = fmt::format("soft {} {}", SOFT_A, SOFT_RC);
  if (overlay)
    in += fmt::format("pair_style hybrid/overlay lj/cut 2.5 soft {}\n"
                      "pair_coeff * * lj/cut 1.0 1.0 2.5\npair_coeff 1 1 {}\n",
                      SOFT_RC, soft);
  else
    in += fmt::format("pair_style hybrid lj/cut 2.5 soft {}\npair_coeff 1 1 lj/cut 1.0 1.0 2.5\n"
                      "pair_coeff 1 2 {}\npair_coeff 2 2 none\n",
                      SOFT_RC, soft);
  return in + "comm_modify cutoff 5.5\nneighbor 0.3 bin\nrun 0\n";
}

// which potentials act between types ti and tj: bit 0 lj/cut, bit 1 soft
int hybrid_terms(bool overlay, int ti, int tj)
{
  if (overlay) return (ti == 1 && tj == 1) ? 3 : 1;
  if (ti == 1 && tj == 1) return 1;
  return (ti != tj) ? 2 : 0;
}

// -grad V_C by brute force over the gathered positions and types (by tag)
// (energy: V_C, its terms' energy, into *energy)
std::vector<double> brute_hybrid(LAMMPS_NS::LAMMPS *lmp, bool overlay, const std::vector<double> &x,
                                 const std::vector<int> &type, const std::set<int> &ctags,
                                 double *energy = nullptr)
{
  double e = 0.0;
  auto *domain = lmp->domain;
  const double L[3] = {domain->xprd, domain->yprd, domain->zprd};
  const int n = (int) type.size();
  std::vector<double> f(3 * n, 0.0);
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      if (!ctags.count(i + 1) && !ctags.count(j + 1)) continue;
      double d[3], r2 = 0.0;
      for (int k = 0; k < 3; k++) {
        d[k] = x[3 * i + k] - x[3 * j + k];
        d[k] -= L[k] * std::round(d[k] / L[k]);
        r2 += d[k] * d[k];
      }
      const int which = hybrid_terms(overlay, type[i], type[j]);
      double fr = 0.0;    // -phi'(r) / r
      if ((which & 1) && r2 < 2.5 * 2.5) {
        const double ir6 = 1.0 / (r2 * r2 * r2);
        fr += 24.0 * ir6 * (2.0 * ir6 - 1.0) / r2;
        e += 4.0 * ir6 * (ir6 - 1.0);
      }
      if ((which & 2) && r2 < SOFT_RC * SOFT_RC) {
        // soft: A (1 + cos(pi r / rc)), -phi' = A pi / rc sin(pi r / rc)
        const double r = std::sqrt(r2);
        fr += SOFT_A * M_PI / SOFT_RC * std::sin(M_PI * r / SOFT_RC) / r;
        e += SOFT_A * (1.0 + std::cos(M_PI * r / SOFT_RC));
      }
      for (int k = 0; k < 3; k++) {
        f[3 * i + k] += fr * d[k];
        f[3 * j + k] -= fr * d[k];
      }
    }
  if (energy) *energy = e;
  return f;
}

std::vector<int> gather_types(LAMMPS_NS::LAMMPS *lmp)
{
  auto *atom = lmp->atom;
  std::vector<int> mine(atom->natoms, 0), all(atom->natoms, 0);
  for (int i = 0; i < atom->nlocal; i++) mine[atom->tag[i] - 1] = atom->type[i];
  MPI_Allreduce(mine.data(), all.data(), (int) all.size(), MPI_INT, MPI_SUM, lmp->world);
  return all;
}

// the sub-styles' energy and virial tallies
std::vector<double> sub_tallies(LAMMPS_NS::LAMMPS *lmp)
{
  std::vector<double> out;
  for (const char *s : {"lj/cut", "soft"}) {
    auto *p = lmp->force->pair_match(s, 1);
    EXPECT_NE(p, nullptr) << s;
    if (!p) continue;
    out.push_back(p->eng_vdwl);
    out.push_back(p->eng_coul);
    for (int k = 0; k < 6; k++) out.push_back(p->virial[k]);
  }
  return out;
}

}    // namespace

TEST(LocalForcesHybrid, SubStylesExactOnAnyRankCount)
{
  for (bool overlay : {false, true}) {
    const std::string sys = overlay ? "hybrid/overlay" : "hybrid";
    HSLammps h;
    h.lines(hybrid_input(overlay));
    auto *atom = h.lmp->atom;
    HSLocalForces lf(h.lmp, "test");
    lf.init();
    ASSERT_TRUE(lf.exact()) << sys << ": " << lf.unrestrictable();
    ASSERT_EQ(lf.rows_unsupported(), "") << sys;
    Reference ref(h.lmp);
    lf.set_reference(ref.get());
    std::vector<double> X, F;
    gather_by_tag(h.lmp, X, F);
    const std::vector<int> T = gather_types(h.lmp);
    double fscale = 0.0;
    for (double v : F) fscale = std::max(fscale, std::fabs(v));
    // the reference itself: with every atom in C it is LAMMPS' full force
    {
      std::set<int> every;
      for (int t = 1; t <= (int) atom->natoms; t++) every.insert(t);
      const auto full = brute_hybrid(h.lmp, overlay, X, T, every);
      for (size_t k = 0; k < F.size(); k++)
        ASSERT_NEAR(full[k], F[k], 1e-12 * fscale) << sys << ": the brute-force reference";
    }
    const std::vector<double> subs0 = sub_tallies(h.lmp);
    auto check = [&](const std::set<int> &ctags, const std::string &what) {
      const auto want = brute_hybrid(h.lmp, overlay, X, T, ctags);
      double **fl = lf.forces();
      std::set<int> seen;
      for (int j : lf.touched()) {
        const int t = (int) atom->tag[j];
        EXPECT_TRUE(seen.insert(t).second) << what << " tag " << t << " reported twice";
        for (int k = 0; k < 3; k++) {
          const double w = ctags.count(t) ? F[3 * (t - 1) + k] : want[3 * (t - 1) + k];
          EXPECT_NEAR(fl[j][k], w, 1e-12 * fscale)
              << what << " tag " << t << (ctags.count(t) ? " member" : " partner") << " dim " << k;
        }
      }
      // (bit for bit: a tally a sub-style never computed may hold garbage, a
      // NaN now and then, which == would call changed; seen on 3 ranks)
      const std::vector<double> subs = sub_tallies(h.lmp);
      ASSERT_EQ(subs.size(), subs0.size());
      EXPECT_EQ(0, memcmp(subs.data(), subs0.data(), subs.size() * sizeof(double)))
          << what << ": a sub-style's tallies changed";
    };
    int cases = 0;
    for (int n : {1, 2, 5, 30})
      for (unsigned seed = 1; seed <= 4; seed++) {
        const std::string what = sys + " |C| " + std::to_string(n) + " seed " + std::to_string(seed);
        // rows: any local copies (ghosts included), no communication
        const auto c = random_copies(h.lmp, n, 500u * seed + n + 11u * h.lmp->comm->me);
        if (!c.empty()) {
          ++cases;
          // with V_C's energy (vci's evaluations: the sub-styles tally it)
          lf.keep_energy(seed > 2);
          const Snapshot before = snap(h.lmp);
          lf.compute_rows(c.data(), (int) c.size());
          expect_unchanged(h.lmp, before, what + " rows");
          std::set<int> ctags;
          for (int j : c) ctags.insert((int) atom->tag[j]);
          check(ctags, what + " rows");
          if (seed > 2) {
            double e = 0.0;
            brute_hybrid(h.lmp, overlay, X, T, ctags, &e);
            EXPECT_NEAR(lf.energy(), e, 1e-12 * std::max(1.0, std::fabs(e))) << what << " V_C";
          }
          lf.keep_energy(false);
          for (int j : c) EXPECT_TRUE(std::find(lf.touched().begin(), lf.touched().end(), j) !=
                                      lf.touched().end()) << what << " rows: member not reported";
        }
        // compute(): owned atoms, collective (C is every rank's), with the
        // terms recorded
        const auto o = random_c(h.lmp, n, 700u * seed + n + 13u * h.lmp->comm->me, seed == 2);
        const Snapshot before = snap(h.lmp);
        lf.compute(o.data(), (int) o.size(), true);
        expect_unchanged(h.lmp, before, what + " compute()");
        std::vector<int> mine, all;
        for (int j : o) mine.push_back((int) atom->tag[j]);
        HardSphere::allgatherv(h.lmp->world, MPI_INT, mine, all);
        check(std::set<int>(all.begin(), all.end()), what + " compute()");
        const auto &tl = lf.term_local();
        const auto &off = lf.term_offsets();
        int covered_pairs = 0;
        for (int t = 0; t < lf.npair_last(); t++) {
          const int a = tl[off[t]], b = tl[off[t] + 1];
          const bool some = hybrid_terms(overlay, atom->type[a], atom->type[b]) != 0;
          EXPECT_TRUE(some) << what << ": a recorded pair term of types " << atom->type[a]
                            << "-" << atom->type[b] << ", which no sub-style computes";
          covered_pairs += some;
        }
        EXPECT_EQ(covered_pairs, lf.npair_last()) << what;
      }
    EXPECT_GE(cases, 12) << sys;
  }
}
