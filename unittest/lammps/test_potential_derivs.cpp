// HSPotential (hs_potential.h): V, V''w, V'''[w,w,.], d2, d2_mixed,
// d3_mixed and d4 of a small molecule in a periodic box (harmonic bonds,
// cosine/squared angles, lj/cut with special_bonds 0 0.5 1, straddling the
// periodic boundary), against the exact series reference of hs_series.h.
// Paths: FDIFF (differences of force evaluations) for everything here; the
// SINGLE path is tested through compute hamiltonian/modified
// (test_hamiltonian_paths.cpp).

#include "hs_test_main.h"

#include "compute_hamiltonian_modified.h"
#include "hs_potential.h"
#include "hs_series.h"

#include "atom.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "pair.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using hs_series::Molecule;
using hs_series::Vec;
using LAMMPS_NS::HSPotential;

namespace {

const double PI = 3.14159265358979323846;

const double POS[5][3] = {{3.4, 0.0, 0.0},
                          {-3.6, 0.3, 0.1},
                          {-2.9, 1.1, -0.2},
                          {-2.0, 0.6, 0.5},
                          {3.0, 1.2, 1.0}};

std::string setup_text(bool angles)
{
  std::string s = "units lj\natom_style molecular\natom_modify map array\nboundary p p p\n"
                  "region box block -4 4 -4 4 -4 4\n"
                  "create_box 1 box bond/types 1 angle/types 1 extra/bond/per/atom 3 "
                  "extra/angle/per/atom 3 extra/special/per/atom 8\n"
                  "mass 1 1.0\n";
  for (auto &p : POS)
    s += "create_atoms 1 single " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
        std::to_string(p[2]) + " units box\n";
  s += "pair_style lj/cut 3.0\npair_coeff 1 1 1.0 1.0\n"
       "bond_style harmonic\nbond_coeff 1 50.0 1.1\n";
  if (angles) s += "angle_style cosine/squared\nangle_coeff 1 5.0 110.0\n";
  s += "special_bonds lj 0.0 0.5 1.0\n"
       "create_bonds single/bond 1 1 2\ncreate_bonds single/bond 1 2 3\n"
       "create_bonds single/bond 1 3 4\n";
  if (angles) s += "create_bonds single/angle 1 1 2 3\ncreate_bonds single/angle 1 2 3 4\n";
  s += "neighbor 0.3 bin\nthermo_style custom step pe\nrun 0\n";
  return s;
}

Molecule reference(bool angles)
{
  Molecule m;
  for (auto &p : POS) m.x.push_back(Vec{p[0], p[1], p[2]});
  m.box[0] = m.box[1] = m.box[2] = 8.0;
  m.special[1] = 0.0;
  m.special[2] = 0.5;
  m.special[3] = 1.0;
  m.bonds = {{0, 1}, {1, 2}, {2, 3}};
  m.kb = 50.0;
  m.r0 = 1.1;
  if (angles) m.angles = {{0, 1, 2}, {1, 2, 3}};
  m.ka = 5.0;
  m.cos0 = std::cos(110.0 * PI / 180.0);
  m.compute_hops();
  return m;
}

// deterministic fields by tag
std::vector<Vec> field(int seed, int n)
{
  std::vector<Vec> u(n);
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++) u[i][k] = std::sin(1.7 * (i + 1) + 2.3 * k + 0.9 * seed);
  return u;
}

struct Fields {
  double **a = nullptr;
  int nmax = 0;
  LAMMPS_NS::LAMMPS *lmp;
  explicit Fields(LAMMPS_NS::LAMMPS *l) : lmp(l)
  {
    nmax = lmp->atom->nmax;
    a = new double *[nmax];
    for (int i = 0; i < nmax; i++) a[i] = new double[3]{0, 0, 0};
  }
  ~Fields()
  {
    for (int i = 0; i < nmax; i++) delete[] a[i];
    delete[] a;
  }
  void set(const std::vector<Vec> &u)
  {
    auto *atom = lmp->atom;
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < 3; k++) a[i][k] = u[atom->tag[i] - 1][k];
  }
  double get(int tag, int k) const { return a[lmp->atom->map(tag)][k]; }
};

// restrict a field to the atoms of a group (by tag list)
std::vector<Vec> restrict(const std::vector<Vec> &u, const std::vector<int> &tags)
{
  std::vector<Vec> r(u.size(), Vec{0, 0, 0});
  for (int t : tags) r[t - 1] = u[t - 1];
  return r;
}

struct Tol {
  double hess, third, d4;
};

void check_all(HSLammps &h, HSPotential &pot, const Molecule &m, const std::vector<int> &gtags,
               const Tol &tol, const char *what)
{
  auto *atom = h.lmp->atom;
  const int n = (int) m.x.size();
  const std::vector<Vec> w = field(1, n), a = field(2, n);
  const std::vector<Vec> wg = restrict(w, gtags), ag = restrict(a, gtags);
  Fields W(h.lmp), A(h.lmp), HW(h.lmp), TW(h.lmp);
  W.set(w);
  A.set(a);

  // state before: x and f (owned + ghost) and pe
  const int nall = atom->nlocal + atom->nghost;
  std::vector<double> xb(3 * nall), fb(3 * nall);
  memcpy(xb.data(), &atom->x[0][0], 3 * nall * sizeof(double));
  memcpy(fb.data(), &atom->f[0][0], 3 * nall * sizeof(double));
  const double evdwl = h.lmp->force->pair->eng_vdwl;

  // scale for relative errors: |w|^2 times the largest V'' entry ~ k_bond
  const double scale2 = std::fabs(m.D(2, wg)) + 1.0;

  pot.hess_third(W.a, HW.a, TW.a);
  for (int t = 1; t <= n; t++) {
    const bool in = std::find(gtags.begin(), gtags.end(), t) != gtags.end();
    for (int k = 0; k < 3; k++) {
      const auto e = m.unit(t - 1, k);
      const double hw_ref = in ? m.d2_mixed(e, wg) : 0.0;
      const double tw_ref = in ? m.d3_mixed(e, wg) : 0.0;
      EXPECT_NEAR(HW.get(t, k), hw_ref, tol.hess * scale2) << what << " V''w atom " << t << " " << k;
      EXPECT_NEAR(TW.get(t, k), tw_ref, tol.third * scale2)
          << what << " V'''[w,w] atom " << t << " " << k;
    }
  }
  pot.hess_vec(W.a, HW.a);
  for (int t = 1; t <= n; t++) {
    const bool in = std::find(gtags.begin(), gtags.end(), t) != gtags.end();
    const auto e = m.unit(t - 1, 1);
    EXPECT_NEAR(HW.get(t, 1), in ? m.d2_mixed(e, wg) : 0.0, tol.hess * scale2) << what;
  }

  const double d2 = pot.d2(W.a), d2r = m.D(2, wg);
  EXPECT_NEAR(d2, d2r, tol.hess * scale2) << what << " d2";
  const double d2m = pot.d2_mixed(A.a, W.a), d2mr = m.d2_mixed(ag, wg);
  EXPECT_NEAR(d2m, d2mr, tol.hess * scale2) << what << " d2_mixed";
  const double d3m = pot.d3_mixed(A.a, W.a), d3mr = m.d3_mixed(ag, wg);
  const double scale3 = std::fabs(m.D(3, wg)) + scale2;
  EXPECT_NEAR(d3m, d3mr, tol.third * scale3) << what << " d3_mixed";
  const double d4 = pot.d4(W.a), d4r = m.D(4, wg);
  const double scale4 = std::fabs(d4r) + scale3;
  EXPECT_NEAR(d4, d4r, tol.d4 * scale4) << what << " d4";
  if (getenv("HS_TEST_VERBOSE"))
    printf("%s: d2 %.3e (rel err %.1e) d2_mixed %.1e d3_mixed %.3e (%.1e) d4 %.3e (%.1e); "
           "fdiff error estimates: hess %.1e third %.1e\n",
           what, d2r, (d2 - d2r) / scale2, (d2m - d2mr) / scale2, d3mr, (d3m - d3mr) / scale3,
           d4r, (d4 - d4r) / scale4, pot.fd_error_hess(), pot.fd_error_third());
  // smooth potentials: the error estimates are far below the NaN threshold
  EXPECT_LT(pot.fd_error_hess(), 1e-4) << what;
  EXPECT_LT(pot.fd_error_third(), 1e-4) << what;

  // x, f and tallies exactly as found
  EXPECT_EQ(0, memcmp(xb.data(), &atom->x[0][0], 3 * nall * sizeof(double))) << what << " x";
  EXPECT_EQ(0, memcmp(fb.data(), &atom->f[0][0], 3 * nall * sizeof(double))) << what << " f";
  EXPECT_EQ(evdwl, h.lmp->force->pair->eng_vdwl) << what << " eng_vdwl";
}

}    // namespace

// the reference itself: V(x) against LAMMPS' pe, and a directional
// derivative against a difference of the reference energy
TEST(PotentialDerivs, ReferenceMatchesLammpsEnergy)
{
  HSLammps h;
  h.lines(setup_text(true));
  Molecule m = reference(true);
  const std::vector<Vec> zero(5, Vec{0, 0, 0});
  EXPECT_NEAR(m.energy(zero).c[0], h.thermo("pe") * 5, 1e-10 * std::fabs(m.energy(zero).c[0]));
}

TEST(PotentialDerivs, FdiffAllStyles)
{
  HSLammps h;
  h.lines(setup_text(true));
  Molecule m = reference(true);
  HSPotential pot(h.lmp, 1, "test");
  pot.init(HSPotential::FDIFF);
  const std::vector<Vec> zero(5, Vec{0, 0, 0});
  EXPECT_NEAR(pot.energy(), m.energy(zero).c[0], 1e-12 * std::fabs(m.energy(zero).c[0]));
  check_all(h, pot, m, {1, 2, 3, 4, 5}, Tol{1e-9, 1e-7, 1e-5}, "fdiff all");
}

TEST(PotentialDerivs, FdiffGroupSubset)
{
  HSLammps h;
  h.lines(setup_text(true));
  h.cmd("group sub id 1 3 5");
  Molecule m = reference(true);
  const int bit = h.lmp->group->bitmask[h.lmp->group->find("sub")];
  HSPotential pot(h.lmp, bit, "test");
  pot.init(HSPotential::FDIFF);
  check_all(h, pot, m, {1, 3, 5}, Tol{1e-9, 1e-7, 1e-5}, "fdiff group");
}

TEST(PotentialDerivs, EvaluateMatchesVerletForces)
{
  HSLammps h;
  h.lines(setup_text(true));
  auto *atom = h.lmp->atom;
  std::vector<double> fb(3 * atom->nlocal);
  memcpy(fb.data(), &atom->f[0][0], fb.size() * sizeof(double));
  HSPotential pot(h.lmp, 1, "test");
  pot.init(HSPotential::AUTO);
  const double pe = h.thermo("pe") * atom->natoms;
  const double v = pot.evaluate(1);
  EXPECT_NEAR(v, pe, 1e-12 * std::fabs(pe));
  for (size_t k = 0; k < fb.size(); k++) EXPECT_NEAR((&atom->f[0][0])[k], fb[k], 1e-12);
  EXPECT_EQ(pot.nevals(), 1.0);
}

// ---- SINGLE and AUTO paths, through compute hamiltonian/modified's
// HSPotential (the compute supplies the neighbor list)

namespace {
HSPotential *compute_potential(HSLammps &h, const char *id)
{
  auto *modify = h.lmp->modify;
  const int ic = modify->find_compute(id);
  if (ic < 0) return nullptr;
  auto *c = dynamic_cast<LAMMPS_NS::ComputeHamiltonianModified *>(modify->compute[ic]);
  return c ? c->potential() : nullptr;
}

std::string with_compute(bool angles, const std::string &args)
{
  std::string s = setup_text(angles);
  s.insert(s.find("thermo_style"), "velocity all create 1.5 87287 loop geom\n"
                                   "compute hm all hamiltonian/modified " + args + "\n");
  s.replace(s.find("thermo_style custom step pe"), 27, "thermo_style custom step pe c_hm[1] c_hm[2] c_hm[3]");
  return s;
}

// path single with another pair style (and coefficients) for lj/cut's
std::string with_pair(const std::string &pair_lines)
{
  std::string s = with_compute(false, "path single");
  const std::string lj = "pair_style lj/cut 3.0\npair_coeff 1 1 1.0 1.0";
  s.replace(s.find(lj), lj.size(), pair_lines);
  return s;
}
}    // namespace

// pair lj/cut (analytic phi'', phi''', phi'''') and bond harmonic
// (analytic) through single(); no angles (path single refuses them)
TEST(PotentialDerivs, SinglePairAndBond)
{
  HSLammps h;
  h.lines(with_compute(false, "path single"));
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  EXPECT_EQ(pot->describe(), "pair lj/cut: single (analytic); bond harmonic: single (analytic)");
  Molecule m = reference(false);
  const double n0 = pot->nevals();
  check_all(h, *pot, m, {1, 2, 3, 4, 5}, Tol{1e-12, 1e-12, 1e-12}, "single");
  EXPECT_EQ(pot->nevals(), n0) << "the single path needs no force evaluation";
}

// three atoms of types 1, 2, 3 under lj/cut: explicit 1-1, 2-2, 3-3 and 1-3
// coefficients, 1-2 and 2-3 mixed (arithmetic), shift yes or no, special
// factors 0 0.5 0.25, compute hm on the single path
static std::string three_type_lj(const char *shift)
{
  return std::string("units lj\natom_style atomic\natom_modify map array\nboundary p p p\n"
                     "region box block -4 4 -4 4 -4 4\ncreate_box 3 box\nmass * 1.0\n"
                     "create_atoms 1 single 0.0 0.0 0.0\ncreate_atoms 2 single 1.1 0.0 0.0\n"
                     "create_atoms 3 single 0.0 1.3 0.0\n"
                     "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n"
                     "pair_coeff 2 2 0.7 1.15 2.2\npair_coeff 3 3 1.3 0.9\n"
                     "pair_coeff 1 3 0.45 0.8 1.9\npair_modify mix arithmetic shift ") +
      shift +
      "\nspecial_bonds lj 0.0 0.5 0.25\n"
      "compute hm all hamiltonian/modified path single\nrun 0\n";
}

// lj/cut's terms are single()'s bits: the inline path (HSPotential::
// lj_inline(): single()'s arithmetic with PairLJCut::init_one()'s
// coefficients rebuilt) against LAMMPS' own single(), two types with a
// mixed and an explicit cross pair, shift yes and no, every special factor
TEST(PotentialDerivs, LJCutTermsAreSinglesBits)
{
  for (const char *shift : {"yes", "no"}) {
    HSLammps h;
    h.lines(three_type_lj(shift));
    HSPotential *pot = compute_potential(h, "hm");
    ASSERT_NE(pot, nullptr);
    EXPECT_TRUE(pot->lj_inline()) << "shift " << shift;
    pot->begin_terms();
    auto *pair = h.lmp->force->pair;
    for (int it = 1; it <= 3; it++)
      for (int jt = 1; jt <= 3; jt++) {
        // atoms 0, 1, 2 have types 1, 2, 3 (single() of lj/cut reads only types)
        const int i = it - 1, j = jt - 1;
        const double rc2 = pair->cutsq[it][jt];
        for (int k = 1; k < 40; k++) {
          const double rsq = rc2 * (0.05 + 0.95 * k / 40.0);
          for (int sb = 0; sb < 4; sb++) {
            double phi[3], ff = 0.0;
            pot->pair_term(i, j, sb, rsq, phi);
            const double fl = sb ? h.lmp->force->special_lj[sb] : 1.0;
            const double e = pair->single(i, j, it, jt, rsq, 1.0, fl, ff);
            const double d1 = -ff * std::sqrt(rsq);
            EXPECT_EQ(0, std::memcmp(&e, &phi[0], sizeof(double)))
                << it << "-" << jt << " rsq " << rsq << " sb " << sb << ": " << e << " vs " << phi[0];
            EXPECT_EQ(0, std::memcmp(&d1, &phi[1], sizeof(double)))
                << it << "-" << jt << " rsq " << rsq << " sb " << sb << ": " << d1 << " vs " << phi[1];
          }
        }
      }
  }
}

// fix adapt changes lj/cut's epsilon during a run (and single()'s
// coefficients with it): the terms still are single()'s, not those of the
// coefficients at init
TEST(PotentialDerivs, LJCutTermsFollowFixAdapt)
{
  HSLammps h;
  h.lines("units lj\natom_style atomic\natom_modify map array\nboundary p p p\n"
          "region box block -4 4 -4 4 -4 4\ncreate_box 2 box\nmass * 1.0\n"
          "create_atoms 1 single 0.0 0.0 0.0\ncreate_atoms 2 single 1.6 0.0 0.0\n"
          "pair_style lj/cut 2.5\npair_coeff * * 1.0 1.0\npair_modify shift yes\n"
          "compute hm all hamiltonian/modified path single\n"
          "variable e equal 1.0+0.01*step\n"
          "fix ad all adapt 1 pair lj/cut epsilon 1 2 v_e\n"
          "thermo_style custom step pe c_hm[1]\nrun 0\nrun 20\n");
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  auto *pair = h.lmp->force->pair;
  int dim = 0;
  const double eps12 = ((double **) pair->extract("epsilon", dim))[1][2];
  ASSERT_GT(eps12, 1.1) << "fix adapt did not change epsilon 1 2";
  pot->begin_terms();    // (a pass over terms starts: the new coefficients taken up)
  EXPECT_TRUE(pot->lj_inline());
  for (int k = 1; k < 20; k++) {
    const double rsq = pair->cutsq[1][2] * (0.1 + 0.9 * k / 20.0);
    for (int ij : {0, 1}) {
      double phi[3], ff = 0.0;
      pot->pair_term(ij, 1 - ij, 0, rsq, phi);
      const double e = pair->single(ij, 1 - ij, 1 + ij, 2 - ij, rsq, 1.0, 1.0, ff);
      EXPECT_EQ(0, std::memcmp(&e, &phi[0], sizeof(double))) << rsq << ": " << e << " vs " << phi[0];
      const double d1 = -ff * std::sqrt(rsq);
      EXPECT_EQ(0, std::memcmp(&d1, &phi[1], sizeof(double))) << rsq;
    }
  }
}

// the table of lj/cut's force kernel (HSPotential::lj_cut_table(),
// hs_ljcut.h) for a method that never initialises the derivative layer
// (cva): PairLJCut's lj1, lj2 for every type pair, so that the kernel's
// force equals single()'s to the bit, also after fix adapt changed epsilon
// during a run (a stale table would give the old forces)
TEST(PotentialDerivs, LJCutKernelTableFollowsFixAdapt)
{
  HSLammps h;
  h.lines("units lj\natom_style atomic\natom_modify map array\nboundary p p p\n"
          "region box block -4 4 -4 4 -4 4\ncreate_box 2 box\nmass * 1.0\n"
          "create_atoms 1 single 0.0 0.0 0.0\ncreate_atoms 2 single 1.6 0.0 0.0\n"
          "pair_style lj/cut 2.5\npair_coeff * * 1.0 1.0\npair_coeff 2 2 0.7 1.1\n"
          "variable e equal 1.0+0.01*step\n"
          "fix ad all adapt 1 pair lj/cut epsilon 1 2 v_e\nrun 0\n");
  HSPotential pot(h.lmp, 1, "test");
  auto *pair = h.lmp->force->pair;
  auto check = [&](const std::string &what) {
    const HardSphere::LJCutTable t = pot.lj_cut_table();
    ASSERT_NE(t.coef, nullptr) << what;
    ASSERT_EQ(t.ntp1, 3) << what;
    for (int it = 1; it <= 2; it++)
      for (int jt = 1; jt <= 2; jt++) {
        const double *c = t.coef + (size_t) t.stride * (it * t.ntp1 + jt);
        for (int k = 1; k < 20; k++)
          for (double fl : {1.0, 0.5}) {
            const double rsq = pair->cutsq[it][jt] * (0.1 + 0.9 * k / 20.0);
            double ff = 0.0;
            pair->single(0, 1, it, jt, rsq, 1.0, fl, ff);
            const double r2inv = 1.0 / rsq, r6inv = r2inv * r2inv * r2inv;
            const double forcelj = r6inv * (c[0] * r6inv - c[1]);
            const double fk = fl * forcelj * r2inv;
            EXPECT_EQ(0, std::memcmp(&ff, &fk, sizeof(double)))
                << what << " types " << it << "-" << jt << " rsq " << rsq << ": " << ff
                << " vs " << fk;
          }
      }
  };
  check("before the run");
  h.lines("run 20\n");
  int dim = 0;
  ASSERT_GT(((double **) pair->extract("epsilon", dim))[1][2], 1.1) << "fix adapt did nothing";
  check("after fix adapt");
  // another pair style: no table
  h.lines("unfix ad\npair_style soft 1.0\npair_coeff * * 1.0\nrun 0\n");
  EXPECT_EQ(pot.lj_cut_table().coef, nullptr);
}

// lj/cut's phi'' for every ordered type pair: the same for (i, j) and
// (j, i), and phi' differenced in r (LAMMPS' init_one() fills epsilon and
// sigma for i <= j only)
TEST(PotentialDerivs, LJCutSecondDerivativeBothTypeOrders)
{
  HSLammps h;
  h.lines(three_type_lj("yes"));
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  pot->begin_terms();
  auto *pair = h.lmp->force->pair;
  for (int it = 1; it <= 3; it++)
    for (int jt = 1; jt <= 3; jt++) {
      const int i = it - 1, j = jt - 1;
      const double rc = std::sqrt(pair->cutsq[it][jt]);
      for (int k = 1; k < 10; k++) {
        const double r = rc * (0.3 + 0.65 * k / 10.0), hh = 1e-3 * r;
        double a[3], b[3];
        pot->pair_term(i, j, 0, r * r, a);
        pot->pair_term(j, i, 0, r * r, b);
        // phi'' from phi' by the O(h^4) central stencil
        double d1[5];
        for (int s = -2; s <= 2; s++) {
          double q[3];
          pot->pair_term(i, j, 0, (r + s * hh) * (r + s * hh), q);
          d1[s + 2] = q[1];
        }
        const double fd = (-d1[4] + 8.0 * d1[3] - 8.0 * d1[1] + d1[0]) / (12.0 * hh);
        EXPECT_NEAR(a[2], b[2], 1e-12 * std::fabs(a[2])) << it << "-" << jt << " r " << r;
        EXPECT_NEAR(a[2], fd, 1e-7 * (std::fabs(a[2]) + std::fabs(a[1]) / r))
            << it << "-" << jt << " r " << r;
      }
    }
}

TEST(PotentialDerivs, SingleGroupSubset)
{
  HSLammps h;
  std::string s = with_compute(false, "path single");
  s.insert(s.find("compute hm"), "group sub id 1 3 5\n");
  s.replace(s.find("compute hm all"), 14, "compute hm sub");
  h.lines(s);
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  check_all(h, *pot, reference(false), {1, 3, 5}, Tol{1e-12, 1e-12, 1e-12}, "single group");
}

// lj/smooth/linear, which has no extract(): its LJ form fitted to single()
// at init gives analytic phi'', phi''', phi'''' (the differences in r of
// the tolerances below miss the 1e-12 of this check by ~10x to 10^5 x)
TEST(PotentialDerivs, SingleLJSmoothLinearFitted)
{
  HSLammps h;
  h.lines(with_pair("pair_style lj/smooth/linear 3.0\npair_coeff 1 1 1.0 1.0"));
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  EXPECT_EQ(pot->describe(), "pair lj/smooth/linear: single (analytic, LJ form fitted); bond "
                             "harmonic: single (analytic)");
  Molecule m = reference(false);
  m.smooth_linear = true;
  check_all(h, *pot, m, {1, 2, 3, 4, 5}, Tol{1e-12, 1e-12, 1e-12}, "single lj/smooth/linear");
}

// r-differences of single(): the same LJ potential as lj/expand with
// shift 0 (no analytic derivatives for that style)
TEST(PotentialDerivs, SingleByRadialDifferences)
{
  HSLammps h;
  h.lines(with_pair("pair_style lj/expand 3.0\npair_coeff 1 1 1.0 1.0 0.0"));
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  EXPECT_EQ(pot->describe(),
            "pair lj/expand: single (differences in r); bond harmonic: single (analytic)");
  check_all(h, *pot, reference(false), {1, 2, 3, 4, 5}, Tol{1e-11, 1e-9, 1e-7}, "single fd-r");
}

// auto: pair and bond on single, angles on fdiff, summed
TEST(PotentialDerivs, AutoMixesPaths)
{
  HSLammps h;
  h.lines(with_compute(true, "path auto"));
  HSPotential *pot = compute_potential(h, "hm");
  ASSERT_NE(pot, nullptr);
  EXPECT_EQ(pot->describe(), "pair lj/cut: single (analytic); bond harmonic: single (analytic); "
                             "angle cosine/squared: fdiff");
  check_all(h, *pot, reference(true), {1, 2, 3, 4, 5}, Tol{1e-9, 1e-7, 1e-5}, "auto");
}

// the three paths give the same compute values, and the corrections
// [4] = dt^2/24 H2, [5] = dt^4/720 H4 agree to the accuracy of the paths
TEST(PotentialDerivs, ComputeValuesAgreeAcrossPaths)
{
  double val[3][5];
  const char *paths[3] = {"path single", "path fdiff", "path auto"};
  for (int p = 0; p < 3; p++) {
    HSLammps h;
    h.lines(with_compute(false, paths[p]));
    // the vector as thermo output of "run 0" computed it
    auto *v = (double *) lammps_extract_compute(h.lmp, "hm", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR);
    ASSERT_NE(v, nullptr);
    for (int k = 0; k < 5; k++) val[p][k] = v[k];
    // cost: fdiff evaluates forces 5 + 4 + 6 times for the vector, 4 for the
    // scalar; single none
    HSPotential *pot = compute_potential(h, "hm");
    ASSERT_NE(pot, nullptr);
    const double n0 = pot->nevals();
    EXPECT_EQ(n0, p == 1 ? 15.0 : 0.0) << paths[p];
    auto *c = h.lmp->modify->compute[h.lmp->modify->find_compute("hm")];
    c->compute_scalar();
    EXPECT_EQ(pot->nevals() - n0, p == 1 ? 4.0 : 0.0) << paths[p];
  }
  EXPECT_GT(std::fabs(val[0][3]), 1e-6 * std::fabs(val[0][0]));
  EXPECT_GT(std::fabs(val[0][4]), 1e-9 * std::fabs(val[0][0]));
  EXPECT_DOUBLE_EQ(val[0][1], val[0][0] + val[0][3]);
  EXPECT_DOUBLE_EQ(val[0][2], val[0][1] + val[0][4]);
  for (int k = 0; k < 3; k++) {
    EXPECT_NEAR(val[1][k], val[0][k], 1e-14 * std::fabs(val[0][k])) << k;
    EXPECT_EQ(val[2][k], val[0][k]) << k;
  }
  EXPECT_NEAR(val[1][3], val[0][3], 1e-10 * std::fabs(val[0][3]));
  EXPECT_NEAR(val[1][4], val[0][4], 1e-5 * std::fabs(val[0][4]));
  if (getenv("HS_TEST_VERBOSE"))
    printf("dt^2/24 H2: single %.15g fdiff %.15g; dt^4/720 H4: single %.15g fdiff %.15g\n",
           val[0][3], val[1][3], val[0][4], val[1][4]);
}

// a pair 1e-5 inside the lj/cut cutoff, moving along its axis: the force
// jumps within the FDIFF steps, so path fdiff reports NaN for H_[2,VV] and
// H_[4,VV]; the single path differentiates the pair term inside the cutoff
TEST(PotentialDerivs, FdiffFlagsCutoffDiscontinuity)
{
  const double rc = 2.5;
  for (const char *path : {"fdiff", "single"}) {
    HSLammps h;
    h.lines(std::string("units lj\natom_style atomic\nboundary p p p\n"
                        "region box block -10 10 -10 10 -10 10\ncreate_box 1 box\n"
                        "create_atoms 1 single 0 0 0 units box\n"
                        "create_atoms 1 single ") +
            std::to_string(rc - 1e-5) + " 0 0 units box\nmass 1 1.0\n"
            "pair_style lj/cut " + std::to_string(rc) + "\npair_coeff 1 1 1.0 1.0\n"
            "group a id 1\ngroup b id 2\n"
            "velocity a set 0.3 0.1 0 units box\nvelocity b set -0.3 0 0 units box\n"
            "compute hm all hamiltonian/modified path " + path + "\n"
            "thermo_style custom step pe c_hm[1] c_hm[2] c_hm[3]\nrun 0\n");
    auto *v = (double *) lammps_extract_compute(h.lmp, "hm", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR);
    ASSERT_NE(v, nullptr);
    EXPECT_TRUE(std::isfinite(v[0])) << path;
    if (std::string(path) == "fdiff") {
      EXPECT_TRUE(std::isnan(v[1])) << path << " " << v[1];
      EXPECT_TRUE(std::isnan(v[2])) << path << " " << v[2];
    } else {
      EXPECT_TRUE(std::isfinite(v[1]) && std::isfinite(v[2])) << path;
    }
  }
}

// atom_style sphere (the hard-sphere case): reverse communication carries
// torques too; paths agree, forces and torques are left as found
TEST(PotentialDerivs, SphereAtomStyle)
{
  double val[2][5];
  const char *paths[2] = {"single", "fdiff"};
  for (int p = 0; p < 2; p++) {
    HSLammps h;
    h.lines(std::string("units lj\natom_style sphere\natom_modify map array\nboundary p p p\n"
                        "region box block -3 3 -3 3 -3 3\ncreate_box 1 box\n"
                        "create_atoms 1 single 2.8 0 0 units box\n"
                        "create_atoms 1 single -2.2 0.3 0 units box\n"
                        "create_atoms 1 single 0 2.7 0.2 units box\n"
                        "create_atoms 1 single 0.3 -2.5 0 units box\n"
                        "set group all diameter 1.0\nset group all mass 1.0\n"
                        "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n"
                        "pair_modify shift yes\n"
                        "velocity all create 1.0 4928459 loop geom\n"
                        "compute hm all hamiltonian/modified path ") +
            paths[p] + "\nthermo_style custom step pe c_hm[1] c_hm[2] c_hm[3]\nrun 0\n");
    auto *atom = h.lmp->atom;
    const int nall = atom->nlocal + atom->nghost;
    std::vector<double> fb(&atom->f[0][0], &atom->f[0][0] + 3 * nall);
    std::vector<double> tb(&atom->torque[0][0], &atom->torque[0][0] + 3 * nall);
    auto *c = h.lmp->modify->compute[h.lmp->modify->find_compute("hm")];
    c->compute_vector();
    for (int k = 0; k < 5; k++) val[p][k] = c->vector[k];
    EXPECT_EQ(0, memcmp(fb.data(), &atom->f[0][0], fb.size() * sizeof(double))) << paths[p];
    EXPECT_EQ(0, memcmp(tb.data(), &atom->torque[0][0], tb.size() * sizeof(double))) << paths[p];
  }
  // the pairs cross the periodic faces (ghosts, newton on)
  EXPECT_GT(std::fabs(val[0][3]), 0.0);
  EXPECT_NEAR(val[1][3], val[0][3], 1e-10 * std::fabs(val[0][3]));
  EXPECT_NEAR(val[1][4], val[0][4], 1e-5 * std::fabs(val[0][4]));
}
