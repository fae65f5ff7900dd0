/* ----------------------------------------------------------------------
   HARDSPHERE package: derivatives of the potential energy through LAMMPS'
   styles. See hs_potential.h and doc/compute_hamiltonian_modified.rst.
------------------------------------------------------------------------- */

#include "hs_potential.h"

#include "hs_compat.h"
#include "hs_fix_rule.h"
#include "hs_jet.h"

#include "angle.h"
#include "atom.h"
#include "atom_vec.h"
#include "bond.h"
#include "comm.h"
#include "dihedral.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "improper.h"
#include "kspace.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mpi.h>
#include <vector>

using namespace LAMMPS_NS;

namespace {
// step factors of the differences along a field, times the length scale L
// (section "FDIFF" of the doc page): eps^(1/5) for V''w (O(s^4) stencil,
// round-off eps/s), about eps^(1/6) when V''w and V'''[w,w,.] share the
// evaluations, eps^(1/7) for V''''[w,w,w,w] (O(s^4), round-off eps/s^3)
constexpr double STEP_HESS = 7.4e-4;
constexpr double STEP_THIRD = 2.0e-3;
constexpr double STEP_D4 = 5.8e-3;
// d4 is NaN when its error estimate exceeds this fraction of its scale
constexpr double D4_TOL = 1.0e-3;

// the energy tallies a style keeps; saved and restored around derivatives
struct Tally {
  double e1 = 0.0, e2 = 0.0, v[6] = {0, 0, 0, 0, 0, 0};
};
}    // namespace

/* ---------------------------------------------------------------------- */

struct HSPotential::Impl : protected Pointers {
  Impl(LAMMPS *lmp, int gb, const std::string &own) : Pointers(lmp), groupbit(gb), owner(own) {}
  ~Impl() { destroy(); }

  int groupbit;
  std::string owner;
  double *nevals = nullptr;
  int initialized = 0;
  Mode mode = AUTO;

  // SINGLE path
  int pair_single = 0, bond_single = 0;
  int pair_lj = 0;          // lj/cut: phi'', phi''', phi'''' analytic
  double **lj_eps = nullptr, **lj_sig = nullptr;
  // lj/cut: phi and phi' by PairLJCut::single()'s own arithmetic inline,
  // with its coefficients lj1..lj4 and offset rebuilt as its init_one()
  // builds them (LJC per type pair, [itype * (ntypes + 1) + jtype]); used
  // only if they reproduce single() bit for bit at init (inline_lj()): the
  // virtual call and its table reads were half the cost of a term in
  // pcva's local projection
  int lj_inline = 0;
  static constexpr int LJC = 7;    // lj1, lj2, lj3, lj4, offset; epsilon, sigma they came from
  std::vector<double> ljc;
  // lj/smooth/linear (no extract()): phi' = -A r^-13 + B r^-7 + C per type
  // pair, fitted to single() at init and verified over [lo, cutoff) (fit_lj())
  int pair_ljfit = 0;
  std::vector<double> ljA, ljB, ljlo;    // [itype * (ntypes + 1) + jtype]; lo < 0: not fitted
  int bond_harm = 0;        // harmonic: phi'' = 2K, phi''' = phi'''' = 0
  std::vector<double> bond_k;
  NeighList *list = nullptr;
  // the frozen cutoff set: in_set[first[ii] + jj] for list entry (ii, jj)
  std::vector<char> in_set;
  std::vector<int> first;
  int frozen_valid = 0, frozen_on = 0;

  // FDIFF path: which contributions the force evaluations include
  int fd_pair = 0, fd_bond = 0, fd_angle = 0, fd_dihedral = 0, fd_improper = 0, fd_kspace = 0;
  std::vector<int> efix;    // fixes with fix_modify energy yes and a post_force()
  // fixes with a post_force(): all, the conservative ones (evaluated again at
  // sub-steps), the held ones (thermostats; hs_fix_rule.h) and unknown ones
  std::vector<int> post_all, post_cons, held, unknown;
  int fd_any = 0;
  double length = 1.0;      // length scale L of the differences
  double err_hess = 0.0, err_third = 0.0;    // see fd_error_hess()

  // scratch, [nmax][3]
  int nmax = 0;
  double **x0 = nullptr, **f0 = nullptr, **t0 = nullptr;
  double **wl = nullptr, **al = nullptr;
  double **fb[5] = {nullptr, nullptr, nullptr, nullptr, nullptr};
  double **sa = nullptr, **sb = nullptr;
  double **s3 = nullptr;    // V'''[w,w] of the single path, ghosts included
  double **s2 = nullptr;    // V'' a of the single path beside V'' w (hess_third_vec())
  Tally tal[6];

  void destroy()
  {
    memory->destroy(x0);
    memory->destroy(f0);
    memory->destroy(t0);
    memory->destroy(wl);
    memory->destroy(al);
    for (auto &b : fb) memory->destroy(b);
    memory->destroy(sa);
    memory->destroy(sb);
    memory->destroy(s3);
    memory->destroy(s2);
    nmax = 0;
  }

  void grow()
  {
    if (atom->nmax <= nmax) return;
    destroy();
    nmax = atom->nmax;
    memory->create(x0, nmax, 3, "hs_potential:x0");
    memory->create(f0, nmax, 3, "hs_potential:f0");
    memory->create(t0, nmax, 3, "hs_potential:t0");
    memory->create(wl, nmax, 3, "hs_potential:wl");
    memory->create(al, nmax, 3, "hs_potential:al");
    for (auto &b : fb) memory->create(b, nmax, 3, "hs_potential:fb");
    memory->create(sa, nmax, 3, "hs_potential:sa");
    memory->create(sb, nmax, 3, "hs_potential:sb");
    memory->create(s3, nmax, 3, "hs_potential:s3");
    memory->create(s2, nmax, 3, "hs_potential:s2");
  }

  bool molecular() const { return atom->molecular != Atom::ATOMIC; }

  /* ---- tallies ---- */

  static void get(Tally &t, double e1, double e2, const double *v)
  {
    t.e1 = e1;
    t.e2 = e2;
    for (int k = 0; k < 6; k++) t.v[k] = v[k];
  }
  static void put(const Tally &t, double &e1, double &e2, double *v)
  {
    e1 = t.e1;
    e2 = t.e2;
    for (int k = 0; k < 6; k++) v[k] = t.v[k];
  }
  void save_tallies()
  {
    double dummy = 0.0;
    if (force->pair) get(tal[0], force->pair->eng_vdwl, force->pair->eng_coul, force->pair->virial);
    if (force->bond) get(tal[1], force->bond->energy, dummy, force->bond->virial);
    if (force->angle) get(tal[2], force->angle->energy, dummy, force->angle->virial);
    if (force->dihedral) get(tal[3], force->dihedral->energy, dummy, force->dihedral->virial);
    if (force->improper) get(tal[4], force->improper->energy, dummy, force->improper->virial);
    if (force->kspace) get(tal[5], force->kspace->energy, dummy, force->kspace->virial);
  }
  void restore_tallies()
  {
    double dummy;
    if (force->pair) put(tal[0], force->pair->eng_vdwl, force->pair->eng_coul, force->pair->virial);
    if (force->bond) put(tal[1], force->bond->energy, dummy, force->bond->virial);
    if (force->angle) put(tal[2], force->angle->energy, dummy, force->angle->virial);
    if (force->dihedral) put(tal[3], force->dihedral->energy, dummy, force->dihedral->virial);
    if (force->improper) put(tal[4], force->improper->energy, dummy, force->improper->virial);
    if (force->kspace) put(tal[5], force->kspace->energy, dummy, force->kspace->virial);
  }

  /* ---- state: x, f, torque of owned and ghost atoms ---- */

  void save()
  {
    grow();
    const size_t n = 3 * sizeof(double) * (atom->nlocal + atom->nghost);
    if (n) {
      memcpy(&x0[0][0], &atom->x[0][0], n);
      memcpy(&f0[0][0], &atom->f[0][0], n);
      if (atom->torque_flag) memcpy(&t0[0][0], &atom->torque[0][0], n);
    }
    save_tallies();
    // ghosts at the owners' current x for both paths (a caller may have
    // moved owned atoms since the last forward communication)
    comm->forward_comm();
  }

  // back to the saved state; fixes in efix recompute their energy at the
  // restored x (their post_force stores it), then f is put back
  void restore()
  {
    const size_t n = 3 * sizeof(double) * (atom->nlocal + atom->nghost);
    if (n) memcpy(&atom->x[0][0], &x0[0][0], n);
    if (!efix.empty()) {
      for (int k : efix) modify->fix[k]->post_force(0);
    }
    if (n) {
      memcpy(&atom->f[0][0], &f0[0][0], n);
      if (atom->torque_flag) memcpy(&atom->torque[0][0], &t0[0][0], n);
    }
    restore_tallies();
  }

  // as FixHardSphere::force_clear (Verlet::force_clear)
  void force_clear()
  {
    size_t nbytes = sizeof(double) * atom->nlocal;
    if (force->newton) nbytes += sizeof(double) * atom->nghost;
    if (nbytes) {
      memset(&atom->f[0][0], 0, 3 * nbytes);
      if (atom->torque_flag) memset(&atom->torque[0][0], 0, 3 * nbytes);
      if (atom->avec->forceclearflag) atom->avec->force_clear(0, nbytes);
    }
  }

  // post_force() of the fixes whose forces are evaluated again at
  // sub-steps: all of them, in LAMMPS' order, unless some are held
  void post_force_conservative(int vflag = 0)
  {
    if (held.empty()) {
      if (!post_all.empty()) modify->post_force(vflag);
    } else
      for (int k : post_cons) modify->fix[k]->post_force(vflag);
  }

  std::string names(const std::vector<int> &ks) const
  {
    std::string s;
    for (int k : ks)
      s += (s.empty() ? "" : ", ") + std::string("fix ") + modify->fix[k]->id + " " +
          modify->fix[k]->style;
    return s;
  }

  // every f (owned and ghost) to zero, for accumulating fields in f
  void zero_f_all()
  {
    const size_t n = 3 * sizeof(double) * (atom->nlocal + atom->nghost);
    if (n) {
      memset(&atom->f[0][0], 0, n);
      if (atom->torque_flag) memset(&atom->torque[0][0], 0, n);
    }
  }

  // the total potential energy from the tallies, as compute pe sums it
  double tally_energy()
  {
    double one = 0.0;
    if (force->pair) one += force->pair->eng_vdwl + force->pair->eng_coul;
    if (molecular()) {
      if (force->bond) one += force->bond->energy;
      if (force->angle) one += force->angle->energy;
      if (force->dihedral) one += force->dihedral->energy;
      if (force->improper) one += force->improper->energy;
    }
    double all = 0.0;
    MPI_Allreduce(&one, &all, 1, MPI_DOUBLE, MPI_SUM, world);
    if (force->kspace) all += force->kspace->energy;    // already global
    if (force->pair && force->pair->tail_flag)
      all += force->pair->etail / (domain->xprd * domain->yprd * domain->zprd);
    all += modify->energy_global();
    return all;
  }

  /* ---- fields ---- */

  // dst = w on owned atoms of the group, 0 elsewhere (owned); the largest
  // |w_i| over all ranks is returned
  double mask_field(double **w, double **dst)
  {
    const int nlocal = atom->nlocal;
    const int *mask = atom->mask;
    double m = 0.0;
    for (int i = 0; i < nlocal; i++) {
      if (mask[i] & groupbit) {
        for (int k = 0; k < 3; k++) dst[i][k] = w[i][k];
        m = MAX(m, dst[i][0] * dst[i][0] + dst[i][1] * dst[i][1] + dst[i][2] * dst[i][2]);
      } else
        dst[i][0] = dst[i][1] = dst[i][2] = 0.0;
    }
    double all = 0.0;
    MPI_Allreduce(&m, &all, 1, MPI_DOUBLE, MPI_MAX, world);
    return sqrt(all);
  }

  void zero_field(double **a)
  {
    for (int i = 0; i < atom->nlocal; i++) a[i][0] = a[i][1] = a[i][2] = 0.0;
  }

  // outputs are derivatives with respect to the group's coordinates only
  void project(double **a)
  {
    const int *mask = atom->mask;
    for (int i = 0; i < atom->nlocal; i++)
      if (!(mask[i] & groupbit)) a[i][0] = a[i][1] = a[i][2] = 0.0;
  }

  double dot_global(double **a, double **b)
  {
    const int *mask = atom->mask;
    double one = 0.0;
    for (int i = 0; i < atom->nlocal; i++)
      if (mask[i] & groupbit) one += a[i][0] * b[i][0] + a[i][1] * b[i][1] + a[i][2] * b[i][2];
    double all = 0.0;
    MPI_Allreduce(&one, &all, 1, MPI_DOUBLE, MPI_SUM, world);
    return all;
  }

  /* ---- FDIFF: force evaluations of the contributions not on SINGLE ---- */

  // x = x0 + s w on the group's owned atoms, ghosts forwarded
  void displace(double s, double **w)
  {
    double **x = atom->x;
    const int *mask = atom->mask;
    for (int i = 0; i < atom->nlocal; i++)
      if (mask[i] & groupbit)
        for (int k = 0; k < 3; k++) x[i][k] = x0[i][k] + s * w[i][k];
    comm->forward_comm();
  }

  // the styles' compute(ef, 0) in Verlet::run's order: all of them, or
  // (fd_only) those whose derivatives come from force differences (the fd_
  // flags are set in init() only for styles that are present and computed)
  void compute_styles(int ef, bool fd_only, int vf = 0)
  {
    if (force->pair && force->pair->compute_flag && (!fd_only || fd_pair))
      force->pair->compute(ef, vf);
    if (molecular()) {
      if (force->bond && (!fd_only || fd_bond)) force->bond->compute(ef, vf);
      if (force->angle && (!fd_only || fd_angle)) force->angle->compute(ef, vf);
      if (force->dihedral && (!fd_only || fd_dihedral)) force->dihedral->compute(ef, vf);
      if (force->improper && (!fd_only || fd_improper)) force->improper->compute(ef, vf);
    }
    if (force->kspace && force->kspace->compute_flag && (!fd_only || fd_kspace))
      force->kspace->compute(ef, vf);
  }

  // -grad of the FDIFF part of V at the current x, owned atoms, into out
  void fd_forces(double **out)
  {
    force_clear();
    compute_styles(0, true);
    if (force->newton) comm->reverse_comm();
    for (int k : efix) modify->fix[k]->post_force(0);
    double **f = atom->f;
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < 3; k++) out[i][k] = f[i][k];
    *nevals += 1.0;
  }

  // FDIFF part of hw = V''w and (if tw) tw = V'''[w,w,.], w masked (owned)
  // F at x0 + m s w, m = -2..2 (m = 0 only for tw); five-point stencils
  void fd_hess_third(double **w, double wmax, double **hw, double **tw)
  {
    const int nlocal = atom->nlocal;
    const int *mask = atom->mask;
    const double s = (tw ? STEP_THIRD : STEP_HESS) * length / wmax;
    const int ms[5] = {-2, -1, 1, 2, 0};
    const int neval = tw ? 5 : 4;
    for (int e = 0; e < neval; e++) {
      displace(ms[e] * s, w);
      fd_forces(fb[e]);
    }
    double **Fm2 = fb[0], **Fm1 = fb[1], **Fp1 = fb[2], **Fp2 = fb[3], **F0 = fb[4];
    // error estimates: O(s^4) minus O(s^2) (three-point) values, the largest
    // over the group, against the natural scales |F| w/L and |F| w^2/L^2
    double loc[5] = {0, 0, 0, 0, 0}, all[5];
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < 3; k++) {
        const double h4 = -(-Fp2[i][k] + 8.0 * Fp1[i][k] - 8.0 * Fm1[i][k] + Fm2[i][k]) / (12.0 * s);
        hw[i][k] += h4;
        double t4 = 0.0;
        if (tw) {
          t4 = -(-Fp2[i][k] + 16.0 * Fp1[i][k] - 30.0 * F0[i][k] + 16.0 * Fm1[i][k] - Fm2[i][k]) /
              (12.0 * s * s);
          tw[i][k] += t4;
        }
        if (!(mask[i] & groupbit)) continue;
        const double h2 = -(Fp1[i][k] - Fm1[i][k]) / (2.0 * s);
        loc[0] = MAX(loc[0], fabs(h4 - h2));
        loc[1] = MAX(loc[1], fabs(h4));
        loc[4] = MAX(loc[4], MAX(fabs(Fp1[i][k]), fabs(Fm1[i][k])));
        if (tw) {
          const double t2 = -(Fp1[i][k] - 2.0 * F0[i][k] + Fm1[i][k]) / (s * s);
          loc[2] = MAX(loc[2], fabs(t4 - t2));
          loc[3] = MAX(loc[3], fabs(t4));
        }
      }
    MPI_Allreduce(loc, all, 5, MPI_DOUBLE, MPI_MAX, world);
    const double sh = all[1] + all[4] * wmax / length;
    const double st = all[3] + all[4] * wmax * wmax / (length * length);
    if (sh > 0.0) err_hess = MAX(err_hess, all[0] / sh);
    if (tw && st > 0.0) err_third = MAX(err_third, all[2] / st);
    if (!std::isfinite(all[0]) || !std::isfinite(all[2])) err_hess = err_third = INFINITY;
  }

  // FDIFF part of V''''[w,w,w,w] from f(m s) = w.F(x0 + m s w), m = +-1..3:
  // f''' = -V''''[w,w,w,w], seven-point O(s^4) stencil. NaN if V is not
  // smooth at this step: the O(s^2) five-point value (its error ~ s^2 f^(5))
  // or the round-off estimate differ by more than D4_TOL of the natural
  // scale |V''''| + |V''[w,w]| wmax^2 / L^2
  double fd_d4(double **w, double wmax)
  {
    const double s = STEP_D4 * length / wmax;
    const int ms[6] = {-3, -2, -1, 1, 2, 3};
    double loc[6], all[6];
    for (int e = 0; e < 6; e++) {
      displace(ms[e] * s, w);
      fd_forces(fb[0]);
      double one = 0.0;
      for (int i = 0; i < atom->nlocal; i++)
        one += w[i][0] * fb[0][i][0] + w[i][1] * fb[0][i][1] + w[i][2] * fb[0][i][2];
      loc[e] = one;
    }
    MPI_Allreduce(loc, all, 6, MPI_DOUBLE, MPI_SUM, world);
    const double fm3 = all[0], fm2 = all[1], fm1 = all[2], fp1 = all[3], fp2 = all[4],
                 fp3 = all[5];
    const double s3 = s * s * s;
    const double hi = -(-fp3 + 8.0 * fp2 - 13.0 * fp1 + 13.0 * fm1 - 8.0 * fm2 + fm3) / (8.0 * s3);
    const double lo = -(fp2 - 2.0 * fp1 + 2.0 * fm1 - fm2) / (2.0 * s3);
    const double rnd = 10.0 * 2.2e-16 *
        (fabs(fp3) + 8.0 * fabs(fp2) + 13.0 * fabs(fp1) + 13.0 * fabs(fm1) + 8.0 * fabs(fm2) +
         fabs(fm3)) /
        (8.0 * s3);
    const double d2 = (fp1 - fm1) / (2.0 * s);
    const double scale = fabs(hi) + fabs(d2) * wmax * wmax / (length * length);
    if (scale > 0.0) err_third = MAX(err_third, MAX(fabs(hi - lo), rnd) / scale);
    if (!(fabs(hi - lo) <= D4_TOL * scale) || !(rnd <= D4_TOL * scale))
      return std::numeric_limits<double>::quiet_NaN();
    return hi;
  }

  /* ---- SINGLE: radial pair and bond terms ---- */

  // phi^(k)(r), k = 1..order, of one pair term
  // (r: sqrt(rsq), from the caller, which often has it)
  void pair_phi(int i, int j, int itype, int jtype, double rsq, double r, double fc, double fl,
                int order, double phi[5])
  {
    Pair *pair = force->pair;
    double fforce = 0.0;
    if (lj_inline) {
      // (set only with pair_lj) phi and phi' as PairLJCut::single(),
      // operation for operation (lj_current() checked at the start of the
      // pass that the coefficients still hold), phi'' .. phi'''' from the
      // same powers of r, in one pass
      HardSphere::lj_cut_phi04(&ljc[LJC * ((size_t) itype * (atom->ntypes + 1) + jtype)], fl,
                               rsq, r, order, phi);
      return;
    }
    phi[0] = pair->single(i, j, itype, jtype, rsq, fc, fl, fforce);
    phi[1] = -fforce * r;
    phi[2] = phi[3] = phi[4] = 0.0;
    if (order < 2) return;
    if (pair_lj) {
      // 4 eps [(sigma/r)^12 - (sigma/r)^6], scaled by the special factor
      // (init_one() sets epsilon and sigma for itype <= jtype only: the
      // other half of the arrays is never written)
      const int lo = std::min(itype, jtype), hi = std::max(itype, jtype);
      HardSphere::lj_derivs(lj_eps[lo][hi], lj_sig[lo][hi], fl, rsq, r, order, phi);
      return;
    }
    if (pair_ljfit) {
      const int k = itype * (atom->ntypes + 1) + jtype;
      if (ljlo[k] >= 0.0 && r >= ljlo[k]) {
        // the linear term's derivatives vanish: LJ's, as for lj/cut above
        const double rinv = 1.0 / r, r6 = rinv * rinv * rinv * rinv * rinv * rinv;
        const double a = fl * ljA[k] * r6 * r6 * rinv, b = fl * ljB[k] * r6 * rinv;
        phi[2] = (13.0 * a - 7.0 * b) * rinv;
        if (order >= 3) phi[3] = (-182.0 * a + 56.0 * b) * rinv * rinv;
        if (order >= 4) phi[4] = (2730.0 * a - 504.0 * b) * rinv * rinv * rinv;
        return;
      }
    }
    pair_phi_fd(i, j, itype, jtype, r, fc, fl, order, phi);
  }

  // the other styles' phi'', ... : differences of single()'s phi' in r (out
  // of line: pair_phi() stays small enough to be inlined in the loops over
  // every term, where the analytic forms are taken)
  __attribute__((noinline)) void pair_phi_fd(int i, int j, int itype, int jtype, double r,
                                             double fc, double fl, int order, double phi[5])
  {
    Pair *pair = force->pair;
    auto dphi = [&](double rr) {
      double ff = 0.0;
      pair->single(i, j, itype, jtype, rr * rr, fc, fl, ff);
      return -ff * rr;
    };
    // not at or beyond the cutoff, where a style may have no values (table)
    HardSphere::radial_derivs_fd(dphi, r, phi[1], r / 16.0, order, phi,
                                 sqrt(pair->cutsq[itype][jtype]));
  }

  // at the start of a pass over terms: epsilon and sigma as the inline
  // coefficients were built from? fix adapt changes them during a run (and
  // single()'s coefficients with them, through the style's reinit()): then
  // they are built and checked again. O(ntypes^2)
  void lj_current()
  {
    if (!pair_lj || ljc.empty()) return;
    const int nt = atom->ntypes;
    for (int it = 1; it <= nt; it++)
      for (int jt = it; jt <= nt; jt++) {
        const double *c = &ljc[LJC * ((size_t) it * (nt + 1) + jt)];
        if (!(lj_eps[it][jt] == c[5] && lj_sig[it][jt] == c[6])) {
          inline_lj();
          return;
        }
      }
  }

  // lj/cut: PairLJCut::init_one()'s coefficients from epsilon, sigma and
  // the cutoff (sqrt(cutsq): exact for a square of a double), the energy
  // shift of pair_modify shift yes or none (Pair::offset_flag is not
  // public: the one that matches single() is taken), kept if single()
  // returns the same bits for energy and force at radii across [0.3, 1) x
  // cutoff with special factors 1, 0.5 and 0.125 for every type pair
  // (another version's single() or init_one() would fail this)
  void inline_lj()
  {
    for (int shifted : {1, 0}) {
      inline_lj(shifted);
      if (lj_inline) return;
    }
  }
  void inline_lj(int shifted)
  {
    Pair *pair = force->pair;
    const int nt = atom->ntypes;
    lj_inline = 0;
    ljc.assign(LJC * (size_t) (nt + 1) * (nt + 1), 0.0);
    for (int it = 1; it <= nt; it++)
      for (int jt = 1; jt <= nt; jt++) {
        // (init_one(i, j) runs for i <= j and mirrors its results)
        const int lo = std::min(it, jt), hi = std::max(it, jt);
        const double eps = lj_eps[lo][hi], sig = lj_sig[lo][hi];
        const double cutsq = pair->cutsq[lo][hi], cut = sqrt(cutsq);
        double *c = &ljc[LJC * ((size_t) it * (nt + 1) + jt)];
        c[5] = eps;
        c[6] = sig;
        c[0] = 48.0 * eps * pow(sig, 12.0);
        c[1] = 24.0 * eps * pow(sig, 6.0);
        c[2] = 4.0 * eps * pow(sig, 12.0);
        c[3] = 4.0 * eps * pow(sig, 6.0);
        if (shifted && (cut > 0.0)) {
          const double ratio = sig / cut;
          c[4] = 4.0 * eps * (pow(ratio, 12.0) - pow(ratio, 6.0));
        } else
          c[4] = 0.0;
      }
    lj_inline = 1;
    for (int it = 1; it <= nt && lj_inline; it++)
      for (int jt = 1; jt <= nt && lj_inline; jt++) {
        const double rc = sqrt(pair->cutsq[it][jt]);
        if (!(rc > 0.0)) continue;
        for (int k = 0; k < 16 && lj_inline; k++)
          for (double fl : {1.0, 0.5, 0.125}) {
            const double r = rc * (0.3 + 0.7 * k / 16.0), rsq = r * r;
            double f1 = 0.0, p[5];
            const double e1 = pair->single(0, 0, it, jt, rsq, 1.0, fl, f1);
            pair_phi(0, 0, it, jt, rsq, r, 1.0, fl, 1, p);
            const double p1 = -f1 * r;    // (pair_phi()'s phi' from single()'s)
            if (!(memcmp(&e1, &p[0], sizeof(double)) == 0 &&
                  memcmp(&p1, &p[1], sizeof(double)) == 0)) {
              lj_inline = 0;
              break;
            }
          }
      }
  }

  // lj/smooth/linear: A, B, C of phi'(r) = -A r^-13 + B r^-7 + C (A = 48 eps
  // sigma^12, B = 24 eps sigma^6, C its force shift) from single() at three
  // radii, kept only where phi' matches at 64 radii in [0.3, 1) x cutoff to
  // 1e-9 of its terms' size; elsewhere the differences in r are used.
  // single() of this style does not use the atom indices.
  void fit_lj()
  {
    Pair *pair = force->pair;
    const int nt = atom->ntypes;
    ljA.assign((nt + 1) * (nt + 1), 0.0);
    ljB = ljA;
    ljlo.assign((nt + 1) * (nt + 1), -1.0);
    auto g = [&](int it, int jt, double r) {
      double ff = 0.0;
      pair->single(0, 0, it, jt, r * r, 1.0, 1.0, ff);
      return -ff * r;
    };
    int nfit = 0;
    for (int it = 1; it <= nt; it++)
      for (int jt = 1; jt <= nt; jt++) {
        const double rc = sqrt(pair->cutsq[it][jt]);
        if (!(rc > 0.0)) continue;
        const double r1 = 0.3 * rc, r2 = 0.55 * rc, r3 = 0.8 * rc;
        // differences with r3 remove C: a 2 x 2 system in A, B (Cramer)
        const double u1 = pow(r1, -13) - pow(r3, -13), w1 = pow(r1, -7) - pow(r3, -7);
        const double u2 = pow(r2, -13) - pow(r3, -13), w2 = pow(r2, -7) - pow(r3, -7);
        const double g3 = g(it, jt, r3);
        const double d1 = g(it, jt, r1) - g3, d2 = g(it, jt, r2) - g3;
        const double det = -u1 * w2 + u2 * w1;
        if (det == 0.0) continue;
        const double A = (d1 * w2 - d2 * w1) / det, B = (-u1 * d2 + u2 * d1) / det;
        const double C = g3 + A * pow(r3, -13) - B * pow(r3, -7);
        bool ok = std::isfinite(A) && std::isfinite(B) && std::isfinite(C);
        for (int k = 0; ok && k < 64; k++) {
          const double r = rc * (0.3 + 0.7 * k / 64.0);
          const double a = A * pow(r, -13), b = B * pow(r, -7);
          ok = fabs(-a + b + C - g(it, jt, r)) <= 1e-9 * (fabs(a) + fabs(b) + fabs(C));
        }
        if (!ok) continue;
        const int k = it * (nt + 1) + jt;
        ljA[k] = A;
        ljB[k] = B;
        ljlo[k] = 0.3 * rc;
        nfit++;
      }
    pair_ljfit = nfit > 0;
  }

  void bond_phi(int type, int i, int j, double rsq, int order, double phi[5])
  {
    Bond *bond = force->bond;
    double fforce = 0.0;
    phi[0] = bond->single(type, rsq, i, j, fforce);
    const double r = sqrt(rsq);
    phi[1] = -fforce * r;
    phi[2] = phi[3] = phi[4] = 0.0;
    if (order < 2) return;
    if (bond_harm) {    // K (r - r0)^2
      phi[2] = 2.0 * bond_k[type];
      return;
    }
    auto dphi = [&](double rr) {
      double ff = 0.0;
      bond->single(type, rr * rr, i, j, ff);
      return -ff * rr;
    };
    HardSphere::radial_derivs_fd(dphi, r, phi[1], r / 16.0, order, phi);
  }

  // calls fn(i, j, del = x_i - x_j, phi[0..order], weight, upd_i, upd_j) for
  // every radial term with an atom in the group. weight counts the term's
  // share of global sums (1/2 for a term a newton-off rank shares with
  // another); upd_* says whether this rank updates that atom's field (owned,
  // or ghost with newton, summed to the owner by reverse communication)
  template <class Fn> void for_each_radial(int order, Fn fn)
  {
    lj_current();
    double **x = atom->x;
    const int *mask = atom->mask;
    const int *type = atom->type;
    const int nlocal = atom->nlocal;
    double phi[5], del[3];

    if (pair_single) {
      if (!list)
        error->all(FLERR,
                   "{}: the single path has no neighbor list (the owner must call "
                   "request_list() after init() and forward init_list())",
                   owner);
      const int newton_pair = force->newton_pair;
      for_each_listed([&](int ii, int jj, int i, int j, int sb, const double *d, double rsq,
                          bool inside) {
        if (!((mask[i] | mask[j]) & groupbit)) return;
        if (frozen_on ? !in_set[first[ii] + jj] : !inside) return;
        pair_phi(i, j, type[i], type[j], rsq, sqrt(rsq), force->special_coul[sb],
                 force->special_lj[sb], order, phi);
        const bool full = newton_pair || j < nlocal;
        fn(i, j, d, phi, full ? 1.0 : 0.5, true, full);
      });
    }

    if (bond_single && molecular()) {
      int **bondlist = neighbor->bondlist;
      const int nb = neighbor->nbondlist;
      const int newton_bond = force->newton_bond;
      for (int n = 0; n < nb; n++) {
        const int i = bondlist[n][0], j = bondlist[n][1], bt = bondlist[n][2];
        if (bt <= 0) continue;
        if (!((mask[i] | mask[j]) & groupbit)) continue;
        for (int k = 0; k < 3; k++) del[k] = x[i][k] - x[j][k];
        const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
        bond_phi(bt, i, j, rsq, order, phi);
        double wgt = 1.0;
        if (!newton_bond) wgt = 0.5 * ((i < nlocal) + (j < nlocal));
        fn(i, j, del, phi, wgt, newton_bond || i < nlocal, newton_bond || j < nlocal);
      }
    }
  }

  bool any_single() const { return pair_single || bond_single; }
  // a style's (or kspace's) terms by force differences
  bool fd_styles() const
  {
    return fd_pair || fd_bond || fd_angle || fd_dihedral || fd_improper || fd_kspace;
  }

  // phi'' of every single term the same whether phi''' is asked for too:
  // not where a pair term's derivatives come from differences, whose
  // stencil near the cutoff follows the highest order asked for
  // (radial_derivs_fd(); bonds' differences have no cutoff)
  bool phi2_order_free() const
  {
    if (!pair_single || pair_lj) return true;
    if (!pair_ljfit) return false;
    const int nt = atom->ntypes;
    for (int it = 1; it <= nt; it++)
      for (int jt = 1; jt <= nt; jt++)
        if (ljlo[it * (nt + 1) + jt] < 0.0) return false;    // (fitted: 0.3 x cutoff)
    return true;
  }

  // calls fn(ii, jj, i, j, sb, del = x_i - x_j, rsq, inside_now) for every
  // pair of the single path's list (all pairs, as the pair style's compute()
  // sees them; sb: the entry's special index)
  template <class Fn> void for_each_listed(Fn fn)
  {
    double **x = atom->x;
    const int *type = atom->type;
    double **cutsq = force->pair->cutsq;
    for (int ii = 0; ii < list->inum; ii++) {
      const int i = list->ilist[ii];
      const int *jlist = list->firstneigh[i];
      const int jnum = list->numneigh[i];
      for (int jj = 0; jj < jnum; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
        const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
        fn(ii, jj, i, j, jlist[jj] >> SBBITS & 3, del, rsq, rsq < cutsq[type[i]][type[j]]);
      }
    }
  }

  // with the frozen set on: the pair style's compute() took the pairs inside
  // the cutoff now; add the frozen pairs that left it and remove the pairs
  // that entered it (single()'s force; ghosts as compute() treats them)
  void frozen_correction()
  {
    if (!frozen_on) return;
    double **f = atom->f;
    const int *type = atom->type;
    const int nlocal = atom->nlocal, newton_pair = force->newton_pair;
    Pair *pair = force->pair;
    for_each_listed([&](int ii, int jj, int i, int j, int sb, const double *del, double rsq,
                        bool now) {
      const bool frozen = in_set[first[ii] + jj];
      if (now == frozen) return;
      double fpair = 0.0;
      pair->single(i, j, type[i], type[j], rsq, force->special_coul[sb], force->special_lj[sb],
                   fpair);
      if (!frozen) fpair = -fpair;
      for (int k = 0; k < 3; k++) {
        f[i][k] += del[k] * fpair;
        if (newton_pair || j < nlocal) f[j][k] -= del[k] * fpair;
      }
    });
  }

  // fill ghost values of a masked field
  void ghosts(double **a) { comm->forward_comm_array(3, a); }

  // SINGLE part of hw (+=) and tw (+=, if tw); w holds w with ghosts. One
  // pass over the terms (each term's phi^(k) once): V''w summed in atom->f,
  // V'''[w,w] in s3; ghost shares go to their owners through atom->f, one
  // reverse communication each. With a (ghosts too): V''a into ha (+=) in
  // the same pass, summed in s2 (each sum in the same order as a pass of
  // its own, so the same bits)
  void single_hess_third(double **w, double **hw, double **tw, double **a = nullptr,
                         double **ha = nullptr)
  {
    const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
    zero_f_all();
    double **f = atom->f;
    if (tw) memset(&s3[0][0], 0, 3 * sizeof(double) * nall);
    if (a) memset(&s2[0][0], 0, 3 * sizeof(double) * nall);
    for_each_radial(tw ? 3 : 2,
                    [&](int i, int j, const double *del, const double *phi, double, bool ui,
                        bool uj) {
                      const double wij[3] = {w[i][0] - w[j][0], w[i][1] - w[j][1],
                                             w[i][2] - w[j][2]};
                      double out[3];
                      HardSphere::radial_hess_vec(del, phi[1], phi[2], wij, out);
                      for (int k = 0; k < 3; k++) {
                        if (ui) f[i][k] += out[k];
                        if (uj) f[j][k] -= out[k];
                      }
                      if (a) {
                        const double aij[3] = {a[i][0] - a[j][0], a[i][1] - a[j][1],
                                               a[i][2] - a[j][2]};
                        HardSphere::radial_hess_vec(del, phi[1], phi[2], aij, out);
                        for (int k = 0; k < 3; k++) {
                          if (ui) s2[i][k] += out[k];
                          if (uj) s2[j][k] -= out[k];
                        }
                      }
                      if (!tw) return;
                      HardSphere::radial_third_ww(del, phi[1], phi[2], phi[3], wij, out);
                      for (int k = 0; k < 3; k++) {
                        if (ui) s3[i][k] += out[k];
                        if (uj) s3[j][k] -= out[k];
                      }
                    });
    if (force->newton) comm->reverse_comm();
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < 3; k++) hw[i][k] += f[i][k];
    // (every f is overwritten; the torques, if any, are still zero)
    // (ha is given with a, as hess_masked() passes them)
    for (auto [src, dst] : {std::make_pair(s3, tw), std::make_pair(s2, ha)}) {
      if (!dst) continue;
      if (force->newton) {
        f = atom->f;
        memcpy(&f[0][0], &src[0][0], 3 * sizeof(double) * nall);
        comm->reverse_comm();
      } else
        f = src;
      for (int i = 0; i < nlocal; i++)
        for (int k = 0; k < 3; k++) dst[i][k] += f[i][k];
    }
  }

  // hw (+=) = V'' w and, if tw, tw (+=) = V'''[w,w,.] for w masked into wm
  // (mask_field(): its largest |w_i| wmax > 0), x, f and tallies left as
  // they were; with am (a masked, single path only: no FDIFF part), ha (+=)
  // = V'' a in the same pass over the terms
  void hess_masked(double **wm, double wmax, double **hw, double **tw, double **am = nullptr,
                   double **ha = nullptr)
  {
    save();
    if (any_single()) {
      ghosts(wm);
      if (am) ghosts(am);
      single_hess_third(wm, hw, tw, am, ha);
    }
    if (fd_any) fd_hess_third(wm, wmax, hw, tw);
    restore();
    project(hw);
    if (tw) project(tw);
    if (am) project(ha);
  }

  // SINGLE part of sum over terms of a scalar g(del, phi, a_ij, b_ij)
  template <class G> double single_sum(int order, double **a, double **b, G g)
  {
    double one = 0.0;
    for_each_radial(order,
                    [&](int i, int j, const double *del, const double *phi, double wgt, bool,
                        bool) {
                      const double aij[3] = {a[i][0] - a[j][0], a[i][1] - a[j][1],
                                             a[i][2] - a[j][2]};
                      const double bij[3] = {b[i][0] - b[j][0], b[i][1] - b[j][1],
                                             b[i][2] - b[j][2]};
                      one += wgt * g(del, phi, aij, bij);
                    });
    double all = 0.0;
    MPI_Allreduce(&one, &all, 1, MPI_DOUBLE, MPI_SUM, world);
    return all;
  }
};

/* ---------------------------------------------------------------------- */

HSPotential::HSPotential(LAMMPS *lmp, int gb, const std::string &own) :
    Pointers(lmp), groupbit(gb), owner(own)
{
  impl = new Impl(lmp, gb, own);
  impl->nevals = &nevals_;
}

HSPotential::~HSPotential()
{
  delete impl;
}

/* ----------------------------------------------------------------------
   which contribution takes which path; the length scale of differences
------------------------------------------------------------------------- */

void HSPotential::init(Mode mode)
{
  Impl &m = *impl;
  m.mode = mode;
  m.pair_single = m.bond_single = m.pair_lj = m.pair_ljfit = m.bond_harm = m.lj_inline = 0;
  m.fd_pair = m.fd_bond = m.fd_angle = m.fd_dihedral = m.fd_improper = m.fd_kspace = 0;
  m.efix.clear();
  const bool molecular = atom->molecular != Atom::ATOMIC;

  auto no_single = [&](const std::string &what) {
    error->all(FLERR,
               "{}: path single is not available for {}: it is not a radial pair or bond "
               "style (use path auto or fdiff)",
               owner, what);
  };

  // the single path sums ghost terms to their owners with comm->reverse_comm()
  // through atom->f (saved and restored with the torque); an atom style
  // whose reverse communication carries other per-atom arrays (e.g.
  // electron, spin) would have them summed too
  const bool reverse_ok = !force->newton || HSCompat::reverse_is_force_and_torque(atom);
  auto no_reverse = [&](const std::string &what) {
    error->all(FLERR,
               "{}: path single for {} needs newton off with atom style {} (its reverse "
               "communication carries more than forces and torques); use path auto or fdiff",
               owner, what, atom->atom_style);
  };

  Pair *pair = force->pair;
  if (pair && pair->compute_flag) {
    const bool can = pair->single_enable && !pair->manybody_flag && reverse_ok;
    if (mode == SINGLE && pair->single_enable && !pair->manybody_flag && !reverse_ok)
      no_reverse(std::string("pair style ") + force->pair_style);
    if (mode != FDIFF && can) {
      m.pair_single = 1;
      const std::string ps = force->pair_style;
      if (ps == "lj/cut" || ps == "lj/cut/opt" || ps == "lj/cut/omp") {
        int dim = 0;
        m.lj_eps = (double **) pair->extract("epsilon", dim);
        m.lj_sig = (double **) pair->extract("sigma", dim);
        m.pair_lj = (m.lj_eps && m.lj_sig) ? 1 : 0;
        if (m.pair_lj) m.inline_lj();
      } else if (ps == "lj/smooth/linear" || ps == "lj/smooth/linear/omp")
        m.fit_lj();
    } else if (mode == SINGLE)
      no_single(std::string("pair style ") + force->pair_style);
    else
      m.fd_pair = 1;
  }
  if (molecular && force->bond) {
    if (mode == SINGLE && !reverse_ok) no_reverse(std::string("bond style ") + force->bond_style);
    if (mode != FDIFF && reverse_ok) {
      m.bond_single = 1;
      if (strcmp(force->bond_style, "harmonic") == 0) {
        // K (r - r0)^2: K from single() at r = r0 + d, where phi' = 2 K d
        // and phi = K d^2 (this LAMMPS' bond harmonic has no extract());
        // both must agree, else the r-differences are used
        m.bond_k.assign(atom->nbondtypes + 1, 0.0);
        m.bond_harm = 1;
        for (int t = 1; t <= atom->nbondtypes; t++) {
          const double r0 = force->bond->equilibrium_distance(t);
          const double d = (r0 > 0.0) ? r0 : 1.0;
          double fforce = 0.0;
          const double e = force->bond->single(t, (r0 + d) * (r0 + d), 0, 0, fforce);
          const double k1 = -fforce * (r0 + d) / (2.0 * d), k2 = e / (d * d);
          if (!(fabs(k1 - k2) <= 1e-12 * fabs(k1))) m.bond_harm = 0;
          m.bond_k[t] = k1;
        }
      }
    } else
      m.fd_bond = 1;
  }
  if (molecular && force->angle) {
    if (mode == SINGLE) no_single(std::string("angle style ") + force->angle_style);
    m.fd_angle = 1;
  }
  if (molecular && force->dihedral) {
    if (mode == SINGLE) no_single(std::string("dihedral style ") + force->dihedral_style);
    m.fd_dihedral = 1;
  }
  if (molecular && force->improper) {
    if (mode == SINGLE) no_single(std::string("improper style ") + force->improper_style);
    m.fd_improper = 1;
  }
  if (force->kspace && force->kspace->compute_flag) {
    if (mode == SINGLE) no_single(std::string("kspace style ") + force->kspace_style);
    m.fd_kspace = 1;
  }
  init_fixes();
  for (int k : m.post_cons) {
    Fix *fix = modify->fix[k];
    if (fix->energy_global_flag && fix->thermo_energy) {
      if (mode == SINGLE) no_single(std::string("fix ") + fix->id + " " + fix->style);
      m.efix.push_back(k);
    }
  }
  m.fd_any = m.fd_styles() || !m.efix.empty();

  // length scale L of the differences along a field: a tenth of the
  // shortest pair cutoff or bond length in play; the skin otherwise
  double len = 0.0;
  if (pair) {
    for (int a = 1; a <= atom->ntypes; a++)
      for (int b = a; b <= atom->ntypes; b++)
        if (pair->cutsq && pair->cutsq[a][b] > 0.0) {
          const double c = sqrt(pair->cutsq[a][b]);
          len = (len > 0.0) ? MIN(len, c) : c;
        }
  }
  if (molecular && force->bond)
    for (int t = 1; t <= atom->nbondtypes; t++) {
      const double r0 = force->bond->equilibrium_distance(t);
      if (r0 > 0.0) len = (len > 0.0) ? MIN(len, r0) : r0;
    }
  if (!(len > 0.0)) len = (neighbor->skin > 0.0) ? 10.0 * neighbor->skin : 10.0;
  m.length = 0.1 * len;
  m.initialized = 1;
}

void HSPotential::set_length(double len)
{
  if (!(len > 0.0)) error->all(FLERR, "{}: length scale must be > 0, got {}", owner, len);
  impl->length = len;
}

double HSPotential::length() const
{
  return impl->length;
}

void HSPotential::reset_fd_error()
{
  impl->err_hess = impl->err_third = 0.0;
}

double HSPotential::fd_error_hess() const
{
  return impl->err_hess;
}

double HSPotential::fd_error_third() const
{
  return impl->err_third;
}

void HSPotential::request_list(Fix *fix, int instance, int id)
{
  if (impl->pair_single) HSCompat::request_half_list(neighbor, fix, instance, 0.0, id);
}

void HSPotential::request_list(Compute *compute, int instance)
{
  if (impl->pair_single) HSCompat::request_half_list(neighbor, compute, instance, 0.0);
}

void HSPotential::init_list(NeighList *ptr)
{
  list = ptr;
  impl->list = ptr;
}

/* ---------------------------------------------------------------------- */

std::string HSPotential::describe() const
{
  const Impl &m = *impl;
  std::string s;
  auto add = [&](const std::string &t) { s += (s.empty() ? "" : "; ") + t; };
  const bool molecular = atom->molecular != Atom::ATOMIC;
  if (force->pair && force->pair->compute_flag)
    add(std::string("pair ") + force->pair_style + ": " +
        (!m.pair_single ? "fdiff"
         : m.pair_lj    ? "single (analytic)"
         : m.pair_ljfit ? "single (analytic, LJ form fitted)"
                        : "single (differences in r)"));
  if (molecular && force->bond)
    add(std::string("bond ") + force->bond_style + ": " +
        (m.bond_single ? (m.bond_harm ? "single (analytic)" : "single (differences in r)")
                       : "fdiff"));
  if (m.fd_angle) add(std::string("angle ") + force->angle_style + ": fdiff");
  if (m.fd_dihedral) add(std::string("dihedral ") + force->dihedral_style + ": fdiff");
  if (m.fd_improper) add(std::string("improper ") + force->improper_style + ": fdiff");
  if (m.fd_kspace) add(std::string("kspace ") + force->kspace_style + ": fdiff");
  for (int k : m.efix)
    add(std::string("fix ") + modify->fix[k]->id + " " + modify->fix[k]->style + ": fdiff");
  if (s.empty()) s = "no potential energy";
  return s;
}

/* ----------------------------------------------------------------------
   a full force evaluation as Verlet::run does it
------------------------------------------------------------------------- */

double HSPotential::evaluate(int eflag)
{
  return evaluate_flags(eflag ? ENERGY_GLOBAL : 0, 0);
}

double HSPotential::evaluate_flags(int eflag, int vflag)
{
  comm->forward_comm();
  impl->force_clear();
  if (modify->n_pre_force) modify->pre_force(vflag);
  impl->compute_styles(eflag, false, vflag);
  impl->frozen_correction();    // forces only; the tallies stay the style's
  if (modify->n_pre_reverse) modify->pre_reverse(eflag, vflag);
  if (force->newton) comm->reverse_comm();
  impl->post_force_conservative(vflag);
  nevals_ += 1.0;
  return (eflag & ENERGY_GLOBAL) ? impl->tally_energy() : 0.0;
}

void HSPotential::conservative_forces(double **out)
{
  Impl &m = *impl;
  m.save();
  m.force_clear();
  if (modify->n_pre_force) modify->pre_force(0);
  m.compute_styles(0, false);
  if (modify->n_pre_reverse) modify->pre_reverse(0, 0);
  if (force->newton) comm->reverse_comm();
  m.post_force_conservative();
  nevals_ += 1.0;
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 3; k++) out[i][k] = f[i][k];
  m.restore();
}

/* ----------------------------------------------------------------------
   the rule of hs_fix_rule.h applied to the fixes of this run
------------------------------------------------------------------------- */

void HSPotential::init_fixes()
{
  Impl &m = *impl;
  m.post_all.clear();
  m.post_cons.clear();
  m.held.clear();
  m.unknown.clear();
  for (int k = 0; k < modify->nfix; k++) {
    if (!(modify->fmask[k] & FixConst::POST_FORCE)) continue;
    if (HardSphere::package_fix(modify->fix[k]->style)) continue;    // (adds no force)
    m.post_all.push_back(k);
    const auto kind = HardSphere::fix_force_kind(modify->fix[k]->style);
    if (kind == HardSphere::FixForceKind::HELD) {
      m.held.push_back(k);
      continue;
    }
    if (kind == HardSphere::FixForceKind::UNKNOWN) m.unknown.push_back(k);
    m.post_cons.push_back(k);
  }
}

bool HSPotential::held_any() const
{
  return !impl->held.empty();
}

std::string HSPotential::held_names() const
{
  return impl->names(impl->held);
}

std::string HSPotential::energyless_names() const
{
  std::vector<int> ks;
  for (int k : impl->post_cons) {
    Fix *fix = modify->fix[k];
    if (fix->energy_global_flag && !fix->thermo_energy) ks.push_back(k);
  }
  return impl->names(ks);
}

std::string HSPotential::unsingled_pair() const
{
  return impl->fd_pair ? std::string("pair ") + force->pair_style : std::string();
}

std::string HSPotential::held_energy_terms() const
{
  const Impl &m = *impl;
  std::string s;
  auto add = [&](const std::string &t) { s += (s.empty() ? "" : ", ") + t; };
  if (m.fd_kspace) add(std::string("kspace ") + force->kspace_style);
  for (int k : m.efix)
    if (HardSphere::base_style(modify->fix[k]->style) != "gravity")
      add(std::string("fix ") + modify->fix[k]->id + " " + modify->fix[k]->style);
  return s;
}

std::string HSPotential::capture_order(const Fix *self) const
{
  std::string before, after;
  bool self_seen = false;
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == self) {
      self_seen = true;
      continue;
    }
    if (!(modify->fmask[k] & FixConst::POST_FORCE) || HardSphere::package_fix(other->style))
      continue;
    if (HardSphere::base_style(other->style) == "enforce2d") continue;    // (zeroes z only)
    const bool is_held =
        HardSphere::fix_force_kind(other->style) == HardSphere::FixForceKind::HELD;
    const std::string name = fmt::format("fix {} {}", other->id, other->style);
    if (!self_seen && is_held) before += (before.empty() ? "" : ", ") + name;
    if (self_seen && !is_held) after += (after.empty() ? "" : ", ") + name;
  }
  if (!before.empty()) return fmt::format("{} come(s) before it in the input", before);
  if (!after.empty()) return fmt::format("{} come(s) after it in the input", after);
  return {};
}

bool HSPotential::bond_by_single() const
{
  return impl->bond_single != 0;
}

std::string HSPotential::unknown_names() const
{
  return impl->names(impl->unknown);
}

double HSPotential::tallied_energy()
{
  return impl->tally_energy();
}

/* ----------------------------------------------------------------------
   V at the current x (compute pe's sum); x, f and tallies unchanged
------------------------------------------------------------------------- */

double HSPotential::energy()
{
  Impl &m = *impl;
  m.save();
  m.force_clear();
  m.compute_styles(1, false);
  for (int k : m.efix) modify->fix[k]->post_force(0);
  nevals_ += 1.0;
  const double v = m.tally_energy();
  m.restore();
  return v;
}

/* ---------------------------------------------------------------------- */

void HSPotential::hess_vec(double **w, double **hw)
{
  hess_third(w, hw, nullptr);
}

void HSPotential::hess_third_vec(double **w, double **hw, double **tw, double **a, double **ha)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  m.grow();
  m.zero_field(hw);
  if (tw) m.zero_field(tw);
  m.zero_field(ha);
  const double wmax = m.mask_field(w, m.wl), amax = m.mask_field(a, m.al);
  // one pass over the terms for both where every term is on the single
  // path and phi'' is the same at order 2 and 3; else a pass each (the
  // FDIFF path's differences, and a phi'' by differences that may take
  // another stencil at order 3 than at order 2 near a cutoff, stay as they
  // were)
  if (wmax > 0.0 && amax > 0.0 && !m.fd_any && m.any_single() && m.phi2_order_free()) {
    m.hess_masked(m.wl, wmax, hw, tw, m.al, ha);
    return;
  }
  if (wmax > 0.0) m.hess_masked(m.wl, wmax, hw, tw);
  if (amax > 0.0) m.hess_masked(m.al, amax, ha, nullptr);
}

void HSPotential::hess_third(double **w, double **hw, double **tw)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  m.grow();
  m.zero_field(hw);
  if (tw) m.zero_field(tw);
  const double wmax = m.mask_field(w, m.wl);
  if (wmax > 0.0) m.hess_masked(m.wl, wmax, hw, tw);
}

double HSPotential::d2(double **w)
{
  return d2_mixed(w, w);
}

double HSPotential::d2_mixed(double **a, double **b)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  m.grow();
  m.mask_field(a, m.al);
  const double bmax = m.mask_field(b, m.wl);
  if (bmax == 0.0) return 0.0;
  double sum = 0.0;
  m.save();
  if (m.any_single()) {
    m.ghosts(m.al);
    m.ghosts(m.wl);
    sum += m.single_sum(2, m.al, m.wl,
                        [](const double *del, const double *phi, const double *aij,
                           const double *bij) {
                          return HardSphere::radial_hess_bilinear(del, phi[1], phi[2], aij, bij);
                        });
  }
  if (m.fd_any) {
    m.zero_field(m.sa);
    m.fd_hess_third(m.wl, bmax, m.sa, nullptr);
    sum += m.dot_global(m.al, m.sa);
  }
  m.restore();
  return sum;
}

double HSPotential::d3_mixed(double **a, double **w)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  m.grow();
  m.mask_field(a, m.al);
  const double wmax = m.mask_field(w, m.wl);
  if (wmax == 0.0) return 0.0;
  double sum = 0.0;
  m.save();
  if (m.any_single()) {
    m.ghosts(m.al);
    m.ghosts(m.wl);
    sum += m.single_sum(3, m.al, m.wl,
                        [](const double *del, const double *phi, const double *aij,
                           const double *wij) {
                          double t[3];
                          HardSphere::radial_third_ww(del, phi[1], phi[2], phi[3], wij, t);
                          return aij[0] * t[0] + aij[1] * t[1] + aij[2] * t[2];
                        });
  }
  if (m.fd_any) {
    m.zero_field(m.sa);
    m.zero_field(m.sb);
    m.fd_hess_third(m.wl, wmax, m.sb, m.sa);
    sum += m.dot_global(m.al, m.sa);
  }
  m.restore();
  return sum;
}

double HSPotential::d4(double **w)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  m.grow();
  const double wmax = m.mask_field(w, m.wl);
  if (wmax == 0.0) return 0.0;
  double sum = 0.0;
  m.save();
  if (m.any_single()) {
    m.ghosts(m.wl);
    sum += m.single_sum(4, m.wl, m.wl,
                        [](const double *del, const double *phi, const double *wij,
                           const double *) {
                          double out[5];
                          HardSphere::radial_directional_fdb(del, wij, phi, out);
                          return out[4];
                        });
  }
  if (m.fd_any) sum += m.fd_d4(m.wl, wmax);
  m.restore();
  return sum;
}

/* ----------------------------------------------------------------------
   the frozen cutoff set of the single pair path (see hs_potential.h)
------------------------------------------------------------------------- */

bool HSPotential::freeze_cutoff_set()
{
  Impl &m = *impl;
  m.frozen_on = 0;
  m.frozen_valid = 0;
  if (!m.pair_single || !m.list || !force->pair) return false;
  comm->forward_comm();
  NeighList *l = m.list;
  m.first.resize(l->inum + 1);
  int tot = 0;
  for (int ii = 0; ii < l->inum; ii++) {
    m.first[ii] = tot;
    tot += l->numneigh[l->ilist[ii]];
  }
  m.first[l->inum] = tot;
  m.in_set.assign(tot, 0);
  m.for_each_listed([&](int ii, int jj, int, int, int, const double *, double, bool in) {
    m.in_set[m.first[ii] + jj] = in ? 1 : 0;
  });
  m.frozen_valid = 1;
  return true;
}

void HSPotential::use_frozen_set(bool on)
{
  impl->frozen_on = (on && impl->frozen_valid) ? 1 : 0;
}

double HSPotential::cutoff_crossings(double &jump)
{
  Impl &m = *impl;
  double loc[2] = {0.0, 0.0}, all[2] = {0.0, 0.0};
  if (m.frozen_valid) {
    comm->forward_comm();
    Pair *pair = force->pair;
    const int *type = atom->type;
    m.for_each_listed([&](int ii, int jj, int i, int j, int, const double *, double, bool in) {
      if (in == (m.in_set[m.first[ii] + jj] != 0)) return;
      // with newton off a pair with a ghost is listed on two ranks
      loc[0] += (force->newton_pair || j < atom->nlocal) ? 1.0 : 0.5;
      double fpair = 0.0;
      const double rc2 = pair->cutsq[type[i]][type[j]];
      pair->single(i, j, type[i], type[j], rc2 * (1.0 - 1e-14), 1.0, 1.0, fpair);
      loc[1] = MAX(loc[1], fabs(fpair) * sqrt(rc2));
    });
  }
  MPI_Allreduce(&loc[0], &all[0], 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&loc[1], &all[1], 1, MPI_DOUBLE, MPI_MAX, world);
  jump = all[1];
  return all[0];
}

/* ----------------------------------------------------------------------
   radial terms of the single path (see hs_potential.h)
------------------------------------------------------------------------- */

void HSPotential::radial_terms(
    const std::function<void(int, int, const double *, double, double, bool, bool)> &fn)
{
  Impl &m = *impl;
  if (!m.initialized) error->one(FLERR, "{}: derivatives used before init()", owner);
  if (!m.any_single()) return;
  comm->forward_comm();
  m.for_each_radial(2, [&](int i, int j, const double *del, const double *phi, double, bool ui,
                           bool uj) { fn(i, j, del, phi[1], phi[2], ui, uj); });
}

bool HSPotential::any_radial() const
{
  return impl->any_single();
}

void HSPotential::pair_term(int i, int j, int sb, double rsq, double phi[3])
{
  const int *type = atom->type;
  double p[5];
  impl->pair_phi(i, j, type[i], type[j], rsq, sqrt(rsq), force->special_coul[sb],
                 force->special_lj[sb], 2, p);
  for (int k = 0; k < 3; k++) phi[k] = p[k];
}

void HSPotential::bond_term(int btype, int i, int j, double rsq, double phi[3])
{
  double p[5];
  impl->bond_phi(btype, i, j, rsq, 2, p);
  for (int k = 0; k < 3; k++) phi[k] = p[k];
}

void HSPotential::pair_term4(int i, int j, int sb, double r, int order, double phi[5])
{
  const int *type = atom->type;
  impl->pair_phi(i, j, type[i], type[j], r * r, r, force->special_coul[sb],
                 force->special_lj[sb], order, phi);
}

void HSPotential::bond_term4(int btype, int i, int j, double rsq, int order, double phi[5])
{
  impl->bond_phi(btype, i, j, rsq, order, phi);
}

bool HSPotential::lj_inline() const
{
  return impl->lj_inline != 0;
}

void HSPotential::begin_terms()
{
  impl->lj_current();
}

HardSphere::LJCutTable HSPotential::lj_cut_table()
{
  HardSphere::LJCutTable t;
  // (lj/cut/opt and lj/cut/omp share single(), not compute()'s order of sums)
  const bool ljcut = force->pair && strcmp(force->pair_style, "lj/cut") == 0;
  Impl &m = *impl;
  if (!m.initialized) {
    // a method without derivatives (cva) never initialises this layer: the
    // coefficients alone, from the pair style of now (its arrays looked up
    // again every time: a new style frees the old ones). Built and checked
    // against single() once, and again when epsilon or sigma change
    // (lj_current(): the same values give the same coefficients)
    const size_t n = Impl::LJC * (size_t) (atom->ntypes + 1) * (atom->ntypes + 1);
    const bool checked = m.lj_inline && m.ljc.size() == n;
    m.pair_lj = m.lj_inline = 0;
    if (!ljcut || !force->pair->single_enable) return t;
    int dim = 0;
    m.lj_eps = (double **) force->pair->extract("epsilon", dim);
    m.lj_sig = (double **) force->pair->extract("sigma", dim);
    if (!m.lj_eps || !m.lj_sig) return t;
    m.pair_lj = 1;
    if (checked) {
      m.lj_inline = 1;
      m.lj_current();
    } else
      m.inline_lj();
  } else
    m.lj_current();
  if (!m.lj_inline || !ljcut) return t;
  t.coef = impl->ljc.data();
  t.stride = Impl::LJC;
  t.ntp1 = atom->ntypes + 1;
  return t;
}

bool HSPotential::radial_only() const
{
  return !impl->fd_any;
}
