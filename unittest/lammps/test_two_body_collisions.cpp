// Two-sphere collisions with no smooth forces, where psa (section 2.1: exact
// event-driven free flight) and cva (section 2.2: velocity Verlet with f = 0
// is exact free flight) give the closed form to round-off. The expected
// outcomes are computed independently of the fix (hs_two_body.h). One suite,
// instantiated per method (test names start with the method).

#include "hs_two_body.h"

using namespace hs_two_body;

namespace {

class TwoBodyCollision : public ::testing::TestWithParam<const char *> {
 protected:
  std::string method() const { return GetParam(); }
};

std::string case_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

}    // namespace


TEST_P(TwoBodyCollision, HeadOnUnequalMasses)
{
  // 1-D: v1' = ((m1-m2) v1 + 2 m2 v2)/(m1+m2), v2' = ((m2-m1) v2 + 2 m1 v1)/(m1+m2)
  const double m1 = 1.0, m2 = 3.0, v1 = 1.0, v2 = -0.5;
  const double v1p = ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2);    // -1.25
  const double v2p = ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2);    //  0.25
  // contact at |x2-x1| = 1 after (2-1)/1.5 = 2/3 time units; run to t = 1.0
  const double tc = 1.0 / 1.5, T = 1.0;
  Body a{{-1.0, 0.0, 0.0}, {v1, 0.0, 0.0}, m1, 0.5};
  Body b{{1.0, 0.0, 0.0}, {v2, 0.0, 0.0}, m2, 0.5};
  // the closed form for this case, independently of the generic helper
  const double x1 = -1.0 + v1 * tc + v1p * (T - tc), x2 = 1.0 + v2 * tc + v2p * (T - tc);
  HSLammps h;
  h.lines(R"(
units lj
atom_style atomic
boundary f f f
atom_modify map array
region box block -10 10 -10 10 -10 10 units box
create_box 2 box
create_atoms 1 single -1 0 0 units box
create_atoms 2 single 1 0 0 units box
mass 1 1.0
mass 2 3.0
group g1 id 1
group g2 id 2
velocity g1 set 1.0 0 0 units box
velocity g2 set -0.5 0 0 units box
comm_modify cutoff 3.0
run 0
timestep 0.01
fix hs all hardsphere/)" + method() + R"( diameter 1.0
run 100
)");
  std::vector<double> x(6), v(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  EXPECT_NEAR(v[0], v1p, 1e-12);
  EXPECT_NEAR(v[3], v2p, 1e-12);
  EXPECT_NEAR(x[0], x1, 1e-12);
  EXPECT_NEAR(x[3], x2, 1e-12);
  for (int k : {1, 2, 4, 5}) {
    EXPECT_EQ(x[k], 0.0);
    EXPECT_EQ(v[k], 0.0);
  }
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);
  // and the generic helper agrees with the closed form
  check_two_body(method(), a, b, 0.01, 100, false, false);
}

TEST_P(TwoBodyCollision, Oblique3D)
{
  Body a{{-1.0, 0.2, -0.1}, {0.9, 0.05, 0.1}, 1.0, 0.5};
  Body b{{0.8, -0.2, 0.25}, {-0.6, 0.15, -0.05}, 2.5, 0.5};
  check_two_body(method(), a, b, 0.01, 200, false, false);
}

TEST_P(TwoBodyCollision, ObliqueGrazingTimestepNotMultiple)
{
  // a contact time that is no multiple of dt and a large impact parameter
  Body a{{-1.5, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1.0, 0.5};
  Body b{{0.5, 0.93, 0.0}, {0.0, 0.0, 0.0}, 1.0, 0.5};
  check_two_body(method(), a, b, 0.0137, 200, false, false);
}

TEST_P(TwoBodyCollision, PerAtomRadiusAndMass)
{
  // atom_style sphere: radii 0.4 and 0.7 (contact distance 1.1), rmass 2 and 0.5
  Body a{{-1.2, 0.1, 0.0}, {1.0, 0.0, 0.05}, 2.0, 0.4};
  Body b{{0.6, -0.3, 0.1}, {-0.4, 0.1, 0.0}, 0.5, 0.7};
  check_two_body(method(), a, b, 0.01, 150, true, false);
}

TEST_P(TwoBodyCollision, AcrossPeriodicBoundary)
{
  // box [0,10)^3 periodic; the spheres approach each other through the x faces
  Body a{{0.6, 5.0, 5.0}, {-1.0, 0.0, 0.0}, 1.0, 0.5};
  Body b{{9.4, 5.3, 5.0}, {0.5, 0.0, 0.0}, 2.0, 0.5};
  check_two_body(method(), a, b, 0.01, 100, false, true, 10.0);
}

TEST_P(TwoBodyCollision, AcrossPeriodicBoundaryPerAtomRadius)
{
  Body a{{5.0, 0.3, 5.0}, {0.0, -1.0, 0.2}, 1.5, 0.6};
  Body b{{5.2, 9.3, 5.1}, {0.1, 0.7, 0.0}, 0.7, 0.3};
  check_two_body(method(), a, b, 0.01, 100, true, true, 10.0);
}

// Two bonded spheres whose pair every neighbor list leaves out (bond_style
// zero, special_bonds lj 0: no force, and the pair excluded): the fix adds
// such pairs itself, each from its lower ID with the partner's image
// nearest it. Across the periodic x face atom->map()'s copy of the partner
// is a box length away and the nearest image is a ghost; in the box's
// middle it is the owned copy. Either way one collision, as free spheres.
// one_three: the pair is 1-3 instead (a chain a - m - b, special_bonds lj
// 1 0 1 leaves only the 1-3 pair out; the filter reads only the left-out
// levels of each special list); m sits far from both and never moves
static void check_bonded_pair(const std::string &method, Body a, Body b, double L,
                              bool one_three = false)
{
  HSLammps h;
  std::string s = R"(units lj
atom_style bond
boundary p p p
atom_modify map array
region box block 0 )" + f17(L) + " 0 " + f17(L) + " 0 " + f17(L) + R"( units box
create_box 2 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 4
)";
  const Vec xm{0.5 * L, 0.86 * L, 0.5 * L};
  s += "create_atoms 1 single " + vec(a.x) + " units box\n";
  if (one_three) s += "create_atoms 1 single " + vec(xm) + " units box\n";
  s += "create_atoms 2 single " + vec(b.x) + " units box\n";
  s += "mass 1 " + f17(a.m) + "\nmass 2 " + f17(b.m) + "\n";
  s += "bond_style zero\nbond_coeff 1\n";
  const int ib = one_three ? 3 : 2;    // b's ID
  if (one_three)
    s += "special_bonds lj 1.0 0.0 1.0\ncreate_bonds single/bond 1 1 2\n"
         "create_bonds single/bond 1 2 3\n";
  else
    s += "special_bonds lj 0.0 1.0 1.0\ncreate_bonds single/bond 1 1 2\n";
  s += "group ga id 1\ngroup gb id " + std::to_string(ib) + "\n";
  s += "velocity ga set " + vec(a.v) + " units box\n";
  s += "velocity gb set " + vec(b.v) + " units box\n";
  s += "comm_modify cutoff 3.0\ntimestep 0.01\n";
  s += "fix hs all hardsphere/" + method + " diameter " + f17(2 * a.r) + "\n";
  s += "thermo_style custom step ke\nthermo_modify norm no\nrun 100\n";
  h.lines(s);
  double tc = 0.0;
  const Vec period{L, L, L};
  exact_two_body(a, b, 1.0, period, tc);
  if (::testing::Test::HasFatalFailure()) return;
  std::vector<double> x(3 * ib), v(3 * ib);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  const int jb = 3 * (ib - 1);
  for (int k = 0; k < 3; k++) {
    double d1 = x[k] - a.x[k], d2 = x[jb + k] - b.x[k];
    d1 -= L * std::round(d1 / L);
    d2 -= L * std::round(d2 / L);
    EXPECT_NEAR(d1, 0.0, 1e-12) << "x1[" << k << "] tc=" << tc;
    EXPECT_NEAR(d2, 0.0, 1e-12) << "x2[" << k << "]";
    EXPECT_NEAR(v[k], a.v[k], 1e-12) << "v1[" << k << "]";
    EXPECT_NEAR(v[jb + k], b.v[k], 1e-12) << "v2[" << k << "]";
    if (one_three) EXPECT_EQ(x[3 + k], xm[k]) << "the middle sphere moved";
  }
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);    // one sphere-sphere collision
}

TEST_P(TwoBodyCollision, BondedPairOutOfTheListsInTheMiddle)
{
  check_bonded_pair(method(), Body{{4.0, 5.0, 5.0}, {1.0, 0.0, 0.0}, 1.0, 0.5},
                    Body{{5.6, 5.2, 4.9}, {-0.5, 0.0, 0.1}, 2.0, 0.5}, 10.0);
}

TEST_P(TwoBodyCollision, BondedPairOutOfTheListsAcrossPeriodicBoundary)
{
  check_bonded_pair(method(), Body{{0.6, 5.0, 5.0}, {-1.0, 0.0, 0.0}, 1.0, 0.5},
                    Body{{9.4, 5.3, 5.0}, {0.5, 0.0, 0.0}, 2.0, 0.5}, 10.0);
}

TEST_P(TwoBodyCollision, BondedOneThreePairOutOfTheLists)
{
  check_bonded_pair(method(), Body{{4.0, 5.0, 5.0}, {1.0, 0.0, 0.0}, 1.0, 0.5},
                    Body{{5.6, 5.2, 4.9}, {-0.5, 0.0, 0.1}, 2.0, 0.5}, 10.0, true);
}

INSTANTIATE_TEST_SUITE_P(PSA, TwoBodyCollision, ::testing::Values("psa"), case_name);
INSTANTIATE_TEST_SUITE_P(CVA, TwoBodyCollision, ::testing::Values("cva"), case_name);
