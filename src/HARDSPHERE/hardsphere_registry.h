/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: style table and registration with a LAMMPS instance.

   The table is filled from the generated headers style_hardsphere_fix.h /
   style_hardsphere_compute.h (written by CMake, cmake/HSStyles.cmake, from
   every src/HARDSPHERE/fix_*.h containing FixStyle( and compute_*.h
   containing ComputeStyle( ), i.e. the same mechanism LAMMPS uses for
   style_fix.h, so it stays in sync with the package automatically.
------------------------------------------------------------------------- */

#ifndef LMP_HARDSPHERE_REGISTRY_H
#define LMP_HARDSPHERE_REGISTRY_H

#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
}

// one style of the package
struct HSStyleEntry {
  const char *kind;    // "fix" or "compute"
  const char *name;    // style name as used in the input, e.g. "hardsphere/cva"
  void *(*creator)(void *lmp, int narg, char **arg);    // returns new Class(lmp, narg, arg)
};

// all fix and compute styles of the package (may be empty)
const std::vector<HSStyleEntry> &hardsphere_styles();

// Insert every style of hardsphere_styles() into lmp->modify's fix_map /
// compute_map, so that the input can use them like built-in styles.
//
// NOTE: the LAMMPS "clear" command destroys and re-creates Modify (and its
// style maps from LAMMPS' own style_fix.h / style_compute.h), which drops
// every style registered this way -- exactly as with styles loaded by the
// 2021 PLUGIN package. Call hardsphere_register_styles() again after "clear"
// (or do not use "clear" in inputs that rely on HARDSPHERE styles).
void hardsphere_register_styles(LAMMPS_NS::LAMMPS *lmp);

#endif
