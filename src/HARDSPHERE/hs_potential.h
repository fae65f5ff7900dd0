/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: derivatives of the potential energy V through
   LAMMPS' own styles (DESIGN.md layer 2), for the modified Hamiltonian
   H_[2,VV] = H + dt^2/24 H2 and H_[4,VV] = H_[2,VV] + dt^4/720 H4 of
   Bond & Leimkuhler (2007), section 3.

   One object serves compute hamiltonian/modified, fix hardsphere/pcva and
   fix hardsphere/mcva. All derivatives are with respect to the coordinates
   of the owned atoms of one group; every per-atom field below is an
   array [nmax][3] read for owned atoms in the group and treated as zero
   elsewhere. Every call leaves atom->x, atom->f and LAMMPS' energy tallies
   as it found them, and is collective (all ranks call it together).

   Paths (doc/compute_hamiltonian_modified.rst says which style takes which):
   - SINGLE: radial pair styles and bond styles through their single()
     (phi'(r) exact; higher r-derivatives analytic or by differences in r),
     contracted along the direction fields with Taylor jets (hs_jet.h);
   - FDIFF: everything else (angles, dihedrals, impropers, many-body pair
     styles, kspace, force fixes) by differences of full force evaluations
     along the direction field.
------------------------------------------------------------------------- */

#ifndef LMP_HS_POTENTIAL_H
#define LMP_HS_POTENTIAL_H

#include "hs_ljcut.h"
#include "pointers.h"

#include <functional>
#include <string>

namespace LAMMPS_NS {

class HSPotential : protected Pointers {
 public:
  enum Mode { AUTO = 0, SINGLE = 1, FDIFF = 2 };

  // owner: for error messages, e.g. "fix hardsphere/pcva" or "compute hamiltonian/modified"
  HSPotential(class LAMMPS *, int groupbit, const std::string &owner);
  ~HSPotential() override;

  // call from the owner's init(); mode AUTO takes SINGLE for the styles
  // that allow it and FDIFF for the rest; SINGLE is an error if some
  // contribution cannot take it; FDIFF forces differences for everything
  void init(Mode mode = AUTO);
  // the owner forwards the half list it requested with request_list()
  // (needed by the SINGLE path; instance identifies the request); call
  // request_list() after init(), which decides whether a list is needed
  // (id: the request's id, which the owner's init_list() receives)
  void request_list(class Fix *owner, int instance, int id = 0);
  void request_list(class Compute *owner, int instance);
  void init_list(class NeighList *);

  // a one-line description of the path each contributing style takes
  std::string describe() const;

  // length scale L of the FDIFF differences (init() sets a tenth of the
  // shortest pair cutoff or bond length); an owner may override it after init()
  void set_length(double);
  double length() const;

  // relative error estimates of the FDIFF parts since the last reset:
  // |O(s^4) - O(s^2)| difference values over the natural scales |F| w/L
  // (V''w, d2) and |F| w^2/L^2 (V'''[w,w,.], d3, d4). 1e-8 .. 1e-5 for the
  // smooth potentials of the tests; of order one or more when a force is discontinuous
  // within the steps (e.g. a pair crossing an unsmoothed cutoff), where the
  // differences are meaningless. 0 without FDIFF parts.
  void reset_fd_error();
  double fd_error_hess() const;
  double fd_error_third() const;

  // --- fixes beside the integrator (hs_fix_rule.h, the doc's rule):
  // sorts the fixes with a post_force() into conservative ones (evaluated
  // again by evaluate()) and held ones (thermostats: left to LAMMPS' own
  // evaluation at the step's end). Called by init(); owners that need no
  // derivatives call it from their init() themselves.
  void init_fixes();
  bool held_any() const;
  // "fix ID style" of the held fixes, and of the fixes with forces the
  // rule does not know (treated as conservative), "" if none
  std::string held_names() const;
  std::string unknown_names() const;
  // "fix ID style" of the conservative fixes with an energy that is not in
  // the potential energy (fix_modify ID energy no, most fixes' default),
  // "" if none
  std::string energyless_names() const;
  // the parts of V that pcva's local projection (hs_local_modified.h)
  // cannot restrict to the colliding spheres' terms, "" if none: a pair
  // style without single() (its terms are not known one by one), and the
  // smooth held terms, kspace and fixes with an energy other than fix
  // gravity's (the local engine holds their forces; the projection counts
  // the members' share of their energy by the work of those forces)
  std::string unsingled_pair() const;
  std::string held_energy_terms() const;
  // why LAMMPS' f in the post_force() of fix `self` is not the conservative
  // force alone ("" if it is): a held fix comes before it in the input, or
  // a conservative one after it (they add their forces in the input's order)
  std::string capture_order(const class Fix *self) const;
  // bond terms through bond_term() (the bond style has single()); else a
  // bond is a term of its style's compute(), as angles are
  bool bond_by_single() const;

  // --- a force (re-)evaluation as Verlet::run does it, at the current
  // x: force_clear, pre_force, pair, bonded, kspace, pre_reverse, reverse
  // comm, post_force of every fix except the held ones. With eflag the total
  // potential energy V (the sum compute pe would report, fix energies
  // included) is returned, else 0. This one DOES leave the new forces in
  // atom->f (it is the force evaluation of the fixes' sub-steps); ghosts' x
  // are forward-communicated first.
  double evaluate(int eflag);
  // the same with LAMMPS' eflag / vflag bits passed to the styles and fixes,
  // so that their tallies are those Verlet would leave on this step (a
  // barostat's move re-evaluates a step's end); V returned with ENERGY_GLOBAL
  double evaluate_flags(int eflag, int vflag);

  // the conservative forces of evaluate() at the current x into out (owned
  // atoms); x, f and tallies are left unchanged
  void conservative_forces(double **out);

  // V from LAMMPS' current energy tallies (the sum compute pe reports);
  // valid on steps where LAMMPS tallied energy (update->eflag_global)
  double tallied_energy();

  // --- derivatives at the current x; x, f and tallies are left unchanged
  double energy();                                 // V (global)
  void hess_vec(double **w, double **hw);          // hw = V'' w
  // hw = V'' w and tw = V'''[w,w,.] (the gradient of w^T V'' w) in one pass
  void hess_third(double **w, double **hw, double **tw);
  // hess_third(w, hw, tw) and hess_vec(a, ha), the same results, in one pass
  // over the terms where every term is on the single path (phi'' once per
  // term for both)
  void hess_third_vec(double **w, double **hw, double **tw, double **a, double **ha);
  double d2(double **w);                           // w^T V'' w (global)
  double d2_mixed(double **a, double **b);         // a^T V'' b (global)
  double d3_mixed(double **a, double **w);         // V'''[a,w,w] (global)
  // V''''[w,w,w,w] (global); NaN when the FDIFF differences show that V is
  // not smooth enough at the step size (their error estimate exceeds 1e-3
  // of the natural scale), e.g. a pair within the steps of a cutoff at which
  // its force jumps
  double d4(double **w);

  // --- the cutoff set of the single pair path, frozen (fix hardsphere/mcva).
  // A pair style cut off without smoothing (lj/cut) makes F or V'' jump
  // where a pair crosses its cutoff, so stage equations that move pairs
  // across it can have no solution. freeze_cutoff_set() records, at the
  // current x, which pairs of the list are inside their cutoff; while
  // use_frozen_set(true) is on, evaluate() and the derivatives take exactly
  // these pairs (with single()'s phi continued past the cutoff for pairs
  // that left it), i.e. the smooth potential of that set. False if the
  // pair style is not on the single path (then nothing is frozen).
  bool freeze_cutoff_set();
  void use_frozen_set(bool on);
  // pairs whose inside/outside status at the current x differs from the
  // frozen set (global count); jump: the largest |phi'(rc)| among them (the
  // force the cutoff cuts off). Collective.
  double cutoff_crossings(double &jump);

  // --- the radial terms of the single path (pair and bond styles), for
  // assembling V'' (fix hardsphere/mcva's Newton iteration): fn(i, j, del =
  // x_i - x_j, phi'(r), phi''(r), upd_i, upd_j) for every term with an atom
  // in the group (frozen cutoff set if on); upd_* says whether this rank owns
  // that term's rows for atom i resp. j (i or j local, owned or ghost).
  // radial_only(): true if V has no other (FDIFF) parts
  void radial_terms(
      const std::function<void(int, int, const double *, double, double, bool, bool)> &fn);
  bool any_radial() const;
  bool radial_only() const;
  // one radial term of the single path at squared distance rsq (no cutoff
  // test: the caller's): phi[0..2] = phi, phi'(r), phi''(r) of pair (i, j)
  // with special index sb (0: none), resp. of a bond of type btype
  // pair_term() and bond_term() come in passes over terms: begin_terms()
  // first (pair coefficients changed since the last pass, e.g. by fix
  // adapt, are taken up there)
  void begin_terms();
  void pair_term(int i, int j, int sb, double rsq, double phi[3]);
  void bond_term(int btype, int i, int j, double rsq, double phi[3]);
  // the same to derivative order (<= 4; phi[0..order], the rest 0: analytic
  // for lj/cut, lj/smooth/linear's LJ part and harmonic bonds, else
  // differences of single()'s phi' in r), for mcva's local stages; the pair
  // term's at distance r (not its square: the stages have r)
  void pair_term4(int i, int j, int sb, double r, int order, double phi[5]);
  void bond_term4(int btype, int i, int j, double rsq, int order, double phi[5]);
  // lj/cut's phi and phi' are single()'s arithmetic inline (its
  // coefficients rebuilt and checked bit for bit against single() at init)
  bool lj_inline() const;
  // the same coefficients for a kernel of lj/cut's forces (hs_ljcut.h), as
  // PairLJCut holds them; coef nullptr unless the pair style is lj/cut and
  // they passed the check. Taken up to date first (as begin_terms()); valid
  // until the next call or init()
  HardSphere::LJCutTable lj_cut_table();

  // number of force evaluations done so far: evaluate(), energy() and those
  // of the FDIFF differences (for the owners' counters)
  double nevals() const { return nevals_; }

 protected:
  int groupbit;
  std::string owner;
  double nevals_ = 0.0;
  class NeighList *list = nullptr;
  struct Impl;
  Impl *impl = nullptr;
};

}    // namespace LAMMPS_NS

#endif
