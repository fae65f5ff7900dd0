// fix hardsphere/press: every invalid set-up stops with an error that names
// the problem (each case in its own lmp process, see hs_errors.h).

#include "hs_errors.h"

#include <cstdio>

using hs_errors::expect_error;

namespace {

// n x n x n fcc cells of hard spheres (diameter 1) at number density rho;
// extra goes before the fixes, fixes replaces the default pair of fixes
std::string fluid(const std::string &press, int n = 4, double rho = 0.5,
                  const std::string &extra = "", const std::string &boundary = "p p p",
                  const std::string &hsfix = "fix hs all hardsphere/psa diameter 1.0\n")
{
  char buf[1024];
  snprintf(buf, sizeof(buf),
           "units lj\natom_style atomic\nboundary %s\nlattice fcc %g\n"
           "region box block 0 %d 0 %d 0 %d\ncreate_box 1 box\ncreate_atoms 1 box\n"
           "mass 1 1.0\nvelocity all create 1.0 4412 mom yes\nneighbor 0.3 bin\n"
           "comm_modify cutoff 2.0\ntimestep 0.01\n",
           boundary.c_str(), rho, n, n, n);
  return std::string(buf) + extra + hsfix + press + "\nrun 200\n";
}

const std::string P5 = "fix press all hardsphere/press iso 5 5 0.05 temp 1.0 seed 11";

}    // namespace

TEST(PressErrors, NonPeriodicDimension)
{
  expect_error(fluid(P5, 4, 0.5, "", "p p f"),
               {"hardsphere/press iso scales the z dimension, which is not periodic"});
  expect_error(fluid("fix press all hardsphere/press aniso 5 5 0.05 temp 1.0 seed 11", 4, 0.5,
                     "", "p f p"),
               {"hardsphere/press aniso scales the y dimension, which is not periodic"});
}

TEST(PressErrors, BoxBelowTwiceTheCutoffAtSetup)
{
  // 2 x 2 x 2 cells at density 0.8: box 3.4 < 2 x the LJ cutoff 2.5
  expect_error(fluid(P5, 2, 0.8, "pair_style lj/cut 2.5\npair_coeff * * 0.5 1.0\n"),
               {"box length in x would be", "twice the largest cutoff or contact distance",
                "too small for its cutoffs"});
}

TEST(PressErrors, BoxBelowTwiceTheCutoffDuringTheRun)
{
  // 32 atoms with LJ at P = 50 are pressed towards density ~1, a box of ~3.2
  expect_error(fluid("fix press all hardsphere/press iso 50 50 0.01 temp 1.0 seed 11 every 1 "
                     "delta 0.2 adapt 100000\nrun 20000",
                     2, 0.1, "pair_style lj/cut 2.5\npair_coeff * * 0.5 1.0\n"),
               {"box length in", "would be", "on step", "too small for its cutoffs"});
}

TEST(PressErrors, TargetBeyondReach)
{
  // 4 spheres (one fcc cell) at P* = 50: packing fraction ~0.72 needs a box
  // of 1.4, below two diameters
  expect_error(fluid("fix press all hardsphere/press iso 50 50 0.05 temp 1.0 seed 11", 1, 0.1),
               {"needs packing fraction", "no way to reach it"});
}

TEST(PressErrors, NonPositivePressureOfPureHardSpheres)
{
  expect_error(fluid("fix press all hardsphere/press iso 0 0 0.05 temp 1.0 seed 11"),
               {"target pressure 0 <= 0 with pure hard spheres", "without bound"});
}

TEST(PressErrors, AnotherFixChangesTheBox)
{
  // defined before the barostat: its own check names it
  expect_error(fluid(P5, 4, 0.5, "fix pb all press/berendsen iso 5 5 1.0\n"),
               {"hardsphere/press cannot run beside fix pb press/berendsen", "changes the box too"});
  expect_error(fluid(P5 + "\nfix press2 all hardsphere/press iso 5 5 0.05 temp 1.0 seed 12"),
               {"hardsphere/press cannot run beside fix press hardsphere/press",
                "changes the box too"});
  // defined after it: LAMMPS' own check (Domain::init) comes first
  expect_error(fluid(P5 + "\nfix pb all press/berendsen iso 5 5 1.0"),
               {"multiple fixes change box"});
  // and the hardsphere fixes refuse every box-changing fix but this one
  expect_error(fluid("fix df all deform 1 x scale 0.9"),
               {"hardsphere/psa cannot run beside fix df deform", "fix hardsphere/press"});
}

TEST(PressErrors, MissingKeywordsAndFixes)
{
  expect_error(fluid("fix press all hardsphere/press iso 5 5 0.05 seed 11"),
               {"needs the temp keyword"});
  expect_error(fluid("fix press all hardsphere/press iso 5 5 0.05 temp 1.0"),
               {"needs the seed keyword"});
  expect_error(fluid("fix press all hardsphere/press tri 5 5 0.05 temp 1.0 seed 11"),
               {"expected iso", "or aniso", "got tri"});
  expect_error(fluid("fix press all hardsphere/press aniso 5 5 0.05 temp 1.0 seed 11 couple xw"),
               {"couple must be none, xyz, xy, yz or xz, got xw"});
  expect_error(fluid("fix press all hardsphere/press iso 5 5 0.05 temp 1.0 seed 11 couple xy"),
               {"iso scales x, y and z together", "couple xy needs aniso"});
  expect_error(fluid("fix press all hardsphere/press iso 5 5 0.05 temp 1.0 seed 11 bogus 1"),
               {"Unknown fix hardsphere/press keyword: bogus"});
  expect_error(fluid(P5, 4, 0.5, "fix nve all nve\n", "p p p", ""),
               {"needs a fix of the hardsphere family"});
  expect_error(fluid(P5, 4, 0.5, "neighbor 0.0 bin\n"), {"needs a neighbor skin > 0"});
}
