/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the LAMMPS APIs this package compiles against.

   Tested: 29Sep2021 update 2 (Debian bookworm) and 4Feb2025 (Debian trixie).

   - LAMMPS 24Mar2022 replaced neighbor->request() + NeighRequest flags with
     neighbor->add_request(), and comm->forward_comm_fix(this) with
     comm->forward_comm(this). Our CMake reads the headers and defines
     HS_LAMMPS_NEW_NEIGH_API / HS_LAMMPS_NEW_COMM_API. For a drop-in build
     inside a LAMMPS src/ tree (no CMake of ours), the newer API is assumed
     when platform.h exists (it appeared with the 2022 releases); define the
     macros by hand for development snapshots in between.
   - Later releases made Modify::n_post_force protected (the public count is
     n_post_force_any = post_force + post_force_group fixes); n_post_force()
     below picks whichever the headers have, by overload resolution, so it
     needs no macro and works in drop-in builds too.
   - 4Feb2025 adds the skin to a perpetual list's custom cutoff (Neighbor::
     morph_unique) and requires the communication cutoff to cover it; the
     29Sep2021 version uses the custom cutoff as given. request_half_list()
     with a LAMMPS pointer takes the list's full cutoff (skin included) and
     asks each version for what gives that list.
------------------------------------------------------------------------- */

#ifndef LMP_HS_COMPAT_H
#define LMP_HS_COMPAT_H

#if !defined(HS_LAMMPS_NEW_NEIGH_API) && !defined(HS_LAMMPS_API_DETECTED) && defined(__has_include)
#if __has_include("platform.h")
#define HS_LAMMPS_NEW_NEIGH_API 1
#define HS_LAMMPS_NEW_COMM_API 1
#endif
#endif

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "force.h"
#include "lammps.h"
#include "modify.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair.h"

namespace LAMMPS_NS {
namespace HSCompat {

  // a half neighbor list for a fix; cutoff > 0 gives it its own cutoff,
  // passed to LAMMPS as is (4Feb2025 adds the skin to it, 29Sep2021 does
  // not: the overload with a LAMMPS pointer below hides that), else it has
  // the pair cutoffs and LAMMPS copies or derives it from the pair style's
  // list at no extra build cost. id tells an owner's lists apart in its
  // init_list()
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

  // the object that made a neighbor request (a pair style, fix, ...):
  // public in 29Sep2021, behind an accessor in 4Feb2025
  inline void *request_requestor(const NeighRequest *req)
  {
#if defined(HS_LAMMPS_NEW_NEIGH_API) && HS_LAMMPS_NEW_NEIGH_API
    return req->get_requestor();
#else
    return req->requestor;
#endif
  }

  // LAMMPS versions from this one on add the skin to the custom cutoff of a
  // perpetual list: verified for 4Feb2025 (neighbor.cpp, morph_unique());
  // 29Sep2021 (update 2, = 20220106 git) does not. Releases in between are
  // treated like 2021: their list is then at most one skin larger than
  // needed (never smaller), and LAMMPS may ask for a larger comm cutoff.
  constexpr int FIRST_VERSION_ADDING_SKIN = 20250204;

  inline bool custom_cutoff_adds_skin(const LAMMPS *lmp)
  {
#if defined(HS_LAMMPS_NEW_NEIGH_API) && HS_LAMMPS_NEW_NEIGH_API
    return lmp->num_ver >= FIRST_VERSION_ADDING_SKIN;
#else
    (void) lmp;
    return false;
#endif
  }

  // a perpetual half list for a fix whose pairs reach list_cutoff (the full
  // build cutoff, skin included), or the pair cutoffs if list_cutoff is 0
  inline void request_half_list(LAMMPS *lmp, class Fix *fix, int instance, double list_cutoff,
                                int id = 0)
  {
    double cutoff = list_cutoff;
    if (cutoff > 0.0 && custom_cutoff_adds_skin(lmp)) cutoff -= lmp->neighbor->skin;
    request_half_list(lmp->neighbor, fix, instance, cutoff, id);
  }

  // the ghost cutoff Comm will set up in this run, as known in a fix's
  // init() (before Neighbor::init() sets cutneighmax): the pair cutoff plus
  // skin, or the comm_modify cutoff if larger (Comm::get_comm_cutoff())
  inline double ghost_cutoff_at_init(const LAMMPS *lmp)
  {
    double cut = 0.0;
    if (lmp->force->pair && lmp->force->pair->cutforce > 0.0)
      cut = lmp->force->pair->cutforce + lmp->neighbor->skin;
    return (cut > lmp->comm->cutghostuser) ? cut : lmp->comm->cutghostuser;
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

  // Modify's count of fixes with post_force(): n_post_force_any where it
  // exists (n_post_force itself became protected), else n_post_force
  namespace detail {
    template <class M> auto n_post_force(const M *m, int) -> decltype(m->n_post_force_any)
    {
      return m->n_post_force_any;
    }
    template <class M> int n_post_force(const M *m, long) { return m->n_post_force; }
    template <class M>
    auto n_post_force_respa(const M *m, int) -> decltype(m->n_post_force_respa_any)
    {
      return m->n_post_force_respa_any;
    }
    template <class M> int n_post_force_respa(const M *m, long) { return m->n_post_force_respa; }
  }    // namespace detail

  inline int n_post_force(const Modify *m)
  {
    return detail::n_post_force(m, 0);
  }
  inline int n_post_force_respa(const Modify *m)
  {
    return detail::n_post_force_respa(m, 0);
  }
  // unchanged and public in both versions, here so that callers can use one
  // family of functions for all counters
  inline int n_pre_force(const Modify *m)
  {
    return m->n_pre_force;
  }
  inline int n_pre_reverse(const Modify *m)
  {
    return m->n_pre_reverse;
  }

  // comm->reverse_comm() sums every array the atom style reverses into the
  // owners. The package saves and restores f, and torque where the style has
  // it, around its own calls; any other array (electron's erforce, spin's
  // fm) would be summed a second time
  inline bool reverse_is_force_and_torque(const Atom *atom)
  {
    const int n = atom->avec->size_reverse;
    return n == 3 || (n == 6 && atom->torque_flag);
  }

  // neigh_modify exclude is in effect. Neighbor::exclude says so only from
  // Neighbor::init() on, which runs after the fixes' init() and leaves it
  // unset before the first run (both versions): a fix's init() that read it
  // read garbage there. The counts the command sets are set from the start
  inline bool excludes(const Neighbor *neighbor)
  {
    return neighbor->nex_type || neighbor->nex_group || neighbor->nex_mol;
  }

}    // namespace HSCompat
}    // namespace LAMMPS_NS

#endif
