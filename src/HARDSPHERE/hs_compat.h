/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the two LAMMPS APIs this package compiles against.

   LAMMPS 24Mar2022 replaced neighbor->request() + NeighRequest flags with
   neighbor->add_request(), and comm->forward_comm_fix(this) with
   comm->forward_comm(this). Our CMake reads the headers and defines
   HS_LAMMPS_NEW_NEIGH_API / HS_LAMMPS_NEW_COMM_API. For a drop-in build
   inside a LAMMPS src/ tree (no CMake of ours), the newer API is assumed
   when platform.h exists (it appeared with the 2022 releases); define the
   macros by hand for development snapshots in between.
------------------------------------------------------------------------- */

#ifndef LMP_HS_COMPAT_H
#define LMP_HS_COMPAT_H

#if !defined(HS_LAMMPS_NEW_NEIGH_API) && !defined(HS_LAMMPS_API_DETECTED) && defined(__has_include)
#if __has_include("platform.h")
#define HS_LAMMPS_NEW_NEIGH_API 1
#define HS_LAMMPS_NEW_COMM_API 1
#endif
#endif

#include "comm.h"
#include "neigh_request.h"
#include "neighbor.h"

namespace LAMMPS_NS {
namespace HSCompat {

  // a half neighbor list for a fix; cutoff > 0 gives it its own cutoff
  // (including skin), else it has the pair cutoffs and LAMMPS copies or
  // derives it from the pair style's list at no extra build cost
  // id tells an owner's lists apart in its init_list()
  inline void request_half_list(Neighbor *neighbor, class Fix *fix, int instance, double cutoff,
                                int id = 0)
  {
#if defined(HS_LAMMPS_NEW_NEIGH_API) && HS_LAMMPS_NEW_NEIGH_API
    (void) instance;
    auto *req = neighbor->add_request(fix, NeighConst::REQ_DEFAULT);
    if (cutoff > 0.0) req->set_cutoff(cutoff);
    req->set_id(id);
#else
    int irequest = neighbor->request(fix, instance);
    neighbor->requests[irequest]->id = id;
    neighbor->requests[irequest]->pair = 0;
    neighbor->requests[irequest]->fix = 1;
    if (cutoff > 0.0) {
      neighbor->requests[irequest]->cut = 1;
      neighbor->requests[irequest]->cutoff = cutoff;
    }
#endif
  }

  // the same for a compute (a perpetual list: LAMMPS builds or copies it at
  // every reneighboring, so it is current whenever the compute is invoked)
  inline void request_half_list(Neighbor *neighbor, class Compute *compute, int instance,
                                double cutoff)
  {
#if defined(HS_LAMMPS_NEW_NEIGH_API) && HS_LAMMPS_NEW_NEIGH_API
    (void) instance;
    auto *req = neighbor->add_request(compute, NeighConst::REQ_DEFAULT);
    if (cutoff > 0.0) req->set_cutoff(cutoff);
#else
    int irequest = neighbor->request(compute, instance);
    neighbor->requests[irequest]->pair = 0;
    neighbor->requests[irequest]->compute = 1;
    if (cutoff > 0.0) {
      neighbor->requests[irequest]->cut = 1;
      neighbor->requests[irequest]->cutoff = cutoff;
    }
#endif
  }

  inline void forward_comm_fix(Comm *comm, class Fix *fix)
  {
#if defined(HS_LAMMPS_NEW_COMM_API) && HS_LAMMPS_NEW_COMM_API
    comm->forward_comm(fix);
#else
    comm->forward_comm_fix(fix);
#endif
  }

  inline void reverse_comm_fix(Comm *comm, class Fix *fix)
  {
#if defined(HS_LAMMPS_NEW_COMM_API) && HS_LAMMPS_NEW_COMM_API
    comm->reverse_comm(fix);
#else
    comm->reverse_comm_fix(fix);
#endif
  }

}    // namespace HSCompat
}    // namespace LAMMPS_NS

#endif
