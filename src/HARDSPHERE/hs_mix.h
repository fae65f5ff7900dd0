/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: mix64(), splitmix64's finaliser (Steele, Lea and
   Flood 2014; Vigna's splitmix64.c). A bijection of 64-bit words in which
   every input bit moves every output bit: HSSystem's fingerprint of the
   atoms (order-free sums of mixed IDs and positions) and the local engine's
   choice of the member whose owner runs a cluster (the least mix of the
   members' IDs: the same on every rank, unrelated to where IDs lie).
   LAMMPS-free (unit-tested alone: unittest/math/test_mix.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_MIX_H
#define LMP_HS_MIX_H

#include <cstdint>

namespace HardSphere {

inline uint64_t mix64(uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}    // namespace HardSphere

#endif
