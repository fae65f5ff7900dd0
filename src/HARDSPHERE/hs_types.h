/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the value types and conventions that the fix, the
   shared system layer (hs_system.h), the step engines and the methods all
   use: walls, contact events, impulses and the family's tolerances.
   A class takes the names by deriving from HSTypes (no data, no code).
------------------------------------------------------------------------- */

#ifndef LMP_HS_TYPES_H
#define LMP_HS_TYPES_H

#include "lmptype.h"

namespace LAMMPS_NS {

struct HSTypes {
  enum { PAIR_EVENT = 0, WALL_EVENT = 1 };

  // conventions shared by the family
  static constexpr double BIG = 1.0e300;
  // |g(0)| below this (relative to sigma^2, resp. the diameter) counts as
  // touching; below minus this it is an overlap (a missed collision). Far
  // above round-off in positions, far below any physical overlap.
  static constexpr double TOUCH_TOL = 1.0e-9;
  // consecutive zero-length sub-steps without an impulse before we call it
  // a resting contact, which the impulsive hard-sphere model cannot resolve
  static constexpr int MAX_STUCK = 100;
  // collisions in one step beyond which something is wrong (a sequence of
  // contacts that does not end): MAX_SUBSTEPS_BASE + MAX_SUBSTEPS_PER_SPHERE
  // x the group's size (a dense fluid at a large step has a few per sphere)
  static constexpr bigint MAX_SUBSTEPS_BASE = 1000000;
  static constexpr bigint MAX_SUBSTEPS_PER_SPHERE = 100;
  // screen() results (NEAR: screen_atom<true>()'s, for the closing kick's
  // list of the local engine's quick first guess; FOUND_ERROR: this rank
  // deferred an error to the step's reduction of the flags, HSSystem::
  // reduce_step_flags())
  static constexpr int ACTIVE = 1, FAR = 2, NEAR = 4, FOUND_ERROR = 8;

  struct Wall {
    int dim;         // 0,1,2
    int side;        // -1 = lo face (allowed x >= coord + r), +1 = hi face
    int edge;        // 1 if coord follows the box boundary (EDGE)
    double coord;
  };

  // one collision as found by the rank that predicted it (local indices)
  struct Event {
    int type;
    int i, j;    // i owned; j owned or ghost (pair events)
    int wall;
  };

  // the collision as broadcast to every rank (tags, so any rank can apply it)
  struct Impulse {
    double J[3];      // momentum added to atom i (atom j receives -J)
    double dq[3];     // contact normal q_i - q_j (pair) or wall offset (wall)
    tagint itag, jtag;
    int type;
    int wall;
    int apply;        // 0 for a grazing contact (no normal approach velocity)
    int reflect;      // wall: 1 = exact v_n -> -v_n (elastic R); 0 = add J / m
  };
};

}    // namespace LAMMPS_NS

#endif
