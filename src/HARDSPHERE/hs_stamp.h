/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: epoch stamps. A pass marks items by writing the
   current epoch into their stamp, so "seen in this pass" needs no clearing
   between passes; the stamps are cleared only when the counter wraps.
   LAMMPS-free.
------------------------------------------------------------------------- */

#ifndef LMP_HS_STAMP_H
#define LMP_HS_STAMP_H

#include <algorithm>
#include <cstdint>
#include <vector>

namespace HardSphere {

// a new epoch e for stamp: afterwards no entry equals e
inline void bump_epoch(uint32_t &e, std::vector<uint32_t> &stamp)
{
  if (++e == 0) {
    std::fill(stamp.begin(), stamp.end(), 0u);
    e = 1;
  }
}

}    // namespace HardSphere

#endif
