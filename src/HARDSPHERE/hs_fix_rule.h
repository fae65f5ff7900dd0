/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the rule for force contributions of fixes inside a
   step with collisions (doc/fix_hardsphere.rst, "Fixes beside the
   integrator"). LAMMPS-free: a table from fix style name to kind.

   A collisional step of cva, pcva, mcva and vci evaluates forces again at
   every contact. A force that is a function of the positions (and time)
   only is part of -grad V, or at least of the smooth flow, and is
   evaluated again with the pair, bond, ... styles (CONSERVATIVE). A force
   that is stochastic or depends on velocities (thermostats, friction) is
   not: drawing a fresh random force at every sub-step gives the sub-steps
   less noise than one step's worth while the drag stays, so such a force
   is evaluated once per step by LAMMPS, as beside fix nve, and applied as
   two half kicks around the method's conservative map (HELD). Fixes whose
   own algorithm assumes one velocity-Verlet step of dt per step are
   REFUSED. A fix with forces that the table does not know is treated as
   CONSERVATIVE and named once in a warning (UNKNOWN).
------------------------------------------------------------------------- */

#ifndef LMP_HS_FIX_RULE_H
#define LMP_HS_FIX_RULE_H

#include <string>
#include <vector>

namespace HardSphere {

enum class FixForceKind { CONSERVATIVE, HELD, REFUSED, UNKNOWN };

// the accelerator suffixes LAMMPS gives style names
inline const std::vector<std::string> &accelerator_suffixes()
{
  static const std::vector<std::string> sfx = {"/omp", "/opt",     "/intel",    "/gpu",
                                               "/kk",  "/kk/host", "/kk/device"};
  return sfx;
}

// a style name without an accelerator suffix
inline std::string base_style(const std::string &style)
{
  for (const auto &s : accelerator_suffixes())
    if (style.size() > s.size() && style.compare(style.size() - s.size(), s.size(), s) == 0)
      return style.substr(0, style.size() - s.size());
  return style;
}

// this package's integrators (hardsphere/cva, ...): their post_force() only
// copies f (HSSystem::capture_forces()), it adds no force
inline bool package_fix(const std::string &style_in)
{
  return base_style(style_in).compare(0, 11, "hardsphere/") == 0;
}

// the kind of the forces a fix adds in post_force, by its style name
inline FixForceKind fix_force_kind(const std::string &style_in)
{
  const std::string style = base_style(style_in);
  // functions of positions (and time) only: evaluated again at sub-steps
  static const char *const conservative[] = {
      "addforce", "aveforce", "cmap", "colvars", "drag", "efield", "efield/tip4p", "enforce2d",
      "freeze", "gravity", "indent", "lineforce", "planeforce", "plumed", "restrain", "setforce",
      "smd", "spring", "spring/chunk", "spring/rg", "spring/self", "store/force",
      "accelerate/cos", "wall/colloid", "wall/harmonic", "wall/lj1043", "wall/lj126",
      "wall/lj93", "wall/morse", "wall/table", "wall/region", "wall/ees", "wall/region/ees",
      "rhok", "ave/atom", "ave/time"};
  // stochastic or velocity-dependent: once per step, half kicks around the map
  static const char *const held[] = {
      "langevin", "langevin/eff", "langevin/drude", "langevin/spin", "viscous",
      "viscous/sphere", "wall/gran", "wall/gran/region", "damping/cundall", "ttm",
      "ttm/mod", "ttm/grid", "dpd/energy"};
  // constraint forces computed for one unconstrained Verlet step of dt
  static const char *const refused[] = {"shake", "rattle"};
  for (const char *s : conservative)
    if (style == s) return FixForceKind::CONSERVATIVE;
  for (const char *s : held)
    if (style == s) return FixForceKind::HELD;
  for (const char *s : refused)
    if (style == s) return FixForceKind::REFUSED;
  return FixForceKind::UNKNOWN;
}

// a CONSERVATIVE fix whose post_force() only adds a force of the positions
// (and time) to f, whatever f already holds: the local engine can hold it
// through a collisional step from LAMMPS' forces of the step's start and
// end (f less the restricted terms' force: doc/fix_hardsphere.rst, "Held
// smooth forces"). Not those that set, average, project or zero f (their
// force depends on what f holds when they run) or read it
inline bool adds_force_only(const std::string &style_in)
{
  const std::string style = base_style(style_in);
  if (fix_force_kind(style) != FixForceKind::CONSERVATIVE) return false;
  static const char *const not_additive[] = {"aveforce",   "enforce2d", "freeze",
                                             "lineforce",  "planeforce", "setforce",
                                             "store/force", "ave/atom",  "ave/time"};
  for (const char *s : not_additive)
    if (style == s) return false;
  return true;
}

// a fix that sets, averages, projects or reads f (not adds_force_only())
// of the atoms of its own group and no other: on a group that shares no
// atom with the integrator's (a frozen wall of atoms, a piston) it changes
// no force of the spheres, so the local engine need not hold it
// (HSLocalEngine::limits()). Not unknown fixes: a fix may act beyond its
// group, as fix spring couple or cmap do
inline bool own_group_only(const std::string &style_in)
{
  const std::string style = base_style(style_in);
  static const char *const own[] = {"setforce",   "aveforce",   "freeze",
                                    "lineforce",  "planeforce", "store/force"};
  for (const char *s : own)
    if (style == s) return true;
  return false;
}

// pair styles whose forces read the velocities or draw random numbers:
// LAMMPS' styles that need ghost velocities (dissipative particle dynamics,
// lubrication, granular contacts, SPH) and brownian, dsmc. A collisional
// step of cva, pcva, mcva and vci evaluates the pair forces again at every
// contact as functions of the positions, which such a force is not (a
// random force redrawn at each sub-step, a drag at mid-flight velocities).
// Their names, bare and with the accelerator suffixes LAMMPS gives styles:
// what FixHardSphere::check_fixes_beside() looks for with
// Force::pair_match() among a pair style and its hybrid sub-styles
inline std::vector<std::string> velocity_pair_names()
{
  static const char *const styles[] = {
      "dpd", "dpd/tstat", "dpd/ext", "dpd/ext/tstat", "dpd/fdt", "dpd/fdt/energy",
      "dpd/coul/slater/long", "mdpd", "tdpd", "edpd", "sdpd/taitwater/isothermal", "lubricate",
      "lubricate/poly", "lubricateU", "lubricateU/poly", "brownian", "brownian/poly",
      "gran/hooke", "gran/hooke/history", "gran/hertz/history", "granular", "bpm/spring", "dsmc",
      "rheo", "rheo/solid", "mesocnt/viscous", "sph/lj", "sph/idealgas", "sph/taitwater",
      "sph/taitwater/morris", "smd/ulsph", "smd/tlsph"};
  std::vector<std::string> out;
  for (const char *s : styles) {
    out.emplace_back(s);
    for (const auto &sfx : accelerator_suffixes()) out.push_back(s + sfx);
  }
  return out;
}

}    // namespace HardSphere

#endif
