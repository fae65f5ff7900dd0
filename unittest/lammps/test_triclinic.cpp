// Triclinic boxes. (1) A box declared triclinic with zero tilt is the
// orthogonal box: LAMMPS takes its triclinic paths (box fractions in the
// communication, its triclinic neighbor lists), the physics is the same,
// so each method gives the same collisions and energies to round-off.
// (2) Pure hard spheres in a tilted box (tilts of whole lattice cells, so
// the fcc start fits) follow the Carnahan-Starling pressure and the Enskog
// collision rate and keep the temperature to round-off, as in an
// orthogonal box (test_hardsphere_eos.cpp): a contact missed or doubled
// across a tilted periodic face would show. (3) A wall on a face no tilt
// factor leans (z, with xy tilted) keeps spheres in and energy to the
// method's order. (1) and (2) run for every method with a local form and
// psa, on one rank; the MPI harness (test_mpi_local.sh) checks 1, 2 and 4.

#include "hs_test_main.h"

#include "hs_eos.h"

#include "library.h"

#include <cctype>
#include <cmath>
#include <string>

namespace {

double fix_value(HSLammps &h, const char *id, int i)
{
  auto *p = (double *) lammps_extract_fix(h.lmp, id, 0, 1, i, 0);
  if (!p) return NAN;
  double v = *p;
  lammps_free(p);
  return v;
}

std::string case_name(const ::testing::TestParamInfo<const char *> &info)
{
  // (a test name is letters, digits and underscores: "cva diameter 0.95
  // substep global" -> cva_substep_global)
  std::string s, w;
  for (const char *c = info.param;; c++) {
    if (*c == ' ' || *c == 0) {
      if (!w.empty() && !isdigit((unsigned char) w[0]) && w != "diameter")
        s += (s.empty() ? "" : "_") + w;
      w.clear();
      if (*c == 0) break;
    } else
      w += *c;
  }
  return s;
}

struct Outcome {
  double pe, ke, press, ncoll;
};

// the hard-core LJ fluid (diameter 0.95, lj/cut 2.5, fcc 0.8, T 1.5) in
// a box given by its region command, 200 steps of the fix given
Outcome lj_fluid(const std::string &region, const std::string &fix)
{
  HSLammps h;
  h.lines("units lj\natom_style atomic\natom_modify map array\nlattice fcc 0.8\n" + region + R"(
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.5 4928459 mom yes rot no dist gaussian
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
pair_modify shift yes
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
timestep 0.005
thermo_style custom step pe ke press
thermo_modify norm no
)");
  h.cmd(fix);
  h.cmd("run 200");
  return {h.thermo("pe"), h.thermo("ke"), h.thermo("press"), fix_value(h, "hs", 0)};
}

class TriclinicZeroTilt : public ::testing::TestWithParam<const char *> {};

}    // namespace

TEST_P(TriclinicZeroTilt, IsTheOrthogonalBox)
{
  const std::string fix = std::string("fix hs all hardsphere/") + GetParam();
  const Outcome o = lj_fluid("region box block 0 5 0 5 0 5", fix);
  const Outcome t = lj_fluid("region box prism 0 5 0 5 0 5 0 0 0", fix);
  printf("[ triclinic ] %s: collisions %g / %g, pe %.15g / %.15g\n", GetParam(), o.ncoll, t.ncoll,
         o.pe, t.pe);
  ASSERT_GT(o.ncoll, 100.0);
  EXPECT_EQ(o.ncoll, t.ncoll);
  // (the neighbor lists' order differs: the forces are summed in another order)
  EXPECT_NEAR(t.pe, o.pe, 1e-9 * fabs(o.pe));
  EXPECT_NEAR(t.ke, o.ke, 1e-9 * fabs(o.ke));
  EXPECT_NEAR(t.press, o.press, 1e-8 * fabs(o.press));
}

INSTANTIATE_TEST_SUITE_P(
    Methods, TriclinicZeroTilt,
    ::testing::Values("cva diameter 0.95", "pcva diameter 0.95", "vci diameter 0.95",
                      "psa diameter 0.95", "cva diameter 0.95 substep global"),
    case_name);

class TriclinicHardSpheres : public ::testing::TestWithParam<const char *> {};

TEST_P(TriclinicHardSpheres, CarnahanStarlingInATiltedBox)
{
  // tilts of 2, 1 and 2 lattice cells (LAMMPS allows up to half the box)
  hs_eos::carnahan_starling(GetParam(), "region box prism 0 5 0 5 0 5 2 1 2", "tilted",
                            [](HSLammps &h) {
                              h.cmd("thermo_style custom step temp press ke xy xz yz");
                              h.cmd("run 0");
                              ASSERT_GT(h.thermo("xy"), 1.0);
                              ASSERT_GT(h.thermo("yz"), 1.0);
                            });
}

INSTANTIATE_TEST_SUITE_P(Methods, TriclinicHardSpheres, ::testing::Values("psa", "cva"),
                         case_name);

// hard spheres with LJ attraction between walls at z lo and hi of a box
// tilted in xy (its z faces are planes z = const) over 5 time units: every
// sphere stays a radius inside, wall contacts happen, and the energy error
// is cva's second order (halving dt divides it by ~4; the orthogonal slab
// gives 1.25e-3 and 3.6e-4 per atom)
namespace {
struct SlabRun {
  double nwall, zlow, zhigh, zlo, zhi, demax;
};
SlabRun tilted_slab(double dt)
{
  HSLammps h;
  h.lines(R"(
units lj
atom_style atomic
atom_modify map array
boundary p p f
lattice fcc 0.6
region box prism 0 5 0 5 0 5 2 0 0
create_box 1 box
region inner prism 0 5 0 5 0.3 4.7 2 0 0
create_atoms 1 region inner
mass 1 1.0
velocity all create 1.5 87287 mom yes rot no dist gaussian loop geom
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
pair_modify shift yes
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere/cva diameter 1.0 wall zlo EDGE wall zhi EDGE
thermo_style custom step etotal pe ke
thermo_modify norm yes
variable zmin equal bound(all,zmin)
variable zmax equal bound(all,zmax)
)");
  h.cmd("timestep " + std::to_string(dt));
  h.cmd("run 0");
  char e0[64];
  snprintf(e0, sizeof(e0), "%.17g", h.thermo("etotal"));
  h.lines(std::string("variable de equal abs(etotal-(") + e0 + R"())
fix dE all vector 10 v_de
variable demax equal max(f_dE)
fix zlo all vector 10 v_zmin
fix zhi all vector 10 v_zmax
variable zlow equal min(f_zlo)
variable zhigh equal max(f_zhi)
)");
  h.cmd("run " + std::to_string((int) std::lround(5.0 / dt)));
  auto *b = (double *) lammps_extract_global(h.lmp, "boxlo");
  auto *t = (double *) lammps_extract_global(h.lmp, "boxhi");
  return {fix_value(h, "hs", 2), h.variable("zlow"), h.variable("zhigh"), b ? b[2] : NAN,
          t ? t[2] : NAN, h.variable("demax")};
}
}    // namespace

TEST(TriclinicWalls, WallOnAFaceNoTiltLeans)
{
  const SlabRun a = tilted_slab(0.005), b = tilted_slab(0.0025);
  for (const SlabRun &r : {a, b}) {
    printf("[ triclinic walls ] %g wall contacts, z in [%.4f, %.4f] of [%.4f, %.4f], max |dE| "
           "per atom %.3e\n",
           r.nwall, r.zlow, r.zhigh, r.zlo, r.zhi, r.demax);
    EXPECT_GT(r.nwall, 100.0);
    // the centres stay a radius inside the walls (to the contact tolerance)
    EXPECT_GE(r.zlow, r.zlo + 0.5 - 1e-9);
    EXPECT_LE(r.zhigh, r.zhi - 0.5 + 1e-9);
  }
  EXPECT_LT(a.demax, 3e-3);
  // second order: a ratio of 4 expected, 2.8 allowed (order 1.5)
  EXPECT_GT(a.demax / b.demax, 2.8) << a.demax << " then " << b.demax;
}
