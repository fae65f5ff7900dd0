/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/mcva, the modified collision Verlet
   algorithm (Bond & Leimkuhler 2007, section 3.1).

   A step with no (Verlet-)predicted contact is plain Verlet (the family's
   fix nve step). In a step with a predicted contact every sub-step is the
   2-stage Gauss-Legendre method on the flow of the modified Hamiltonian
   H~ = H_[2,VV] = 1/2 p M^-1 p + V + dt^2/12 v^T V'' v - dt^2/24 grad V^T M^-1 grad V,
   the contact time is refined on that flow, and the impulse conserves H~
   (alpha-hat). See doc/fix_hardsphere_mcva.rst.
------------------------------------------------------------------------- */

#ifndef LMP_HS_METHOD_MCVA_H
#define LMP_HS_METHOD_MCVA_H

#include "hs_method.h"
#include "hs_newton.h"

#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class HSLocalModified;

class HSMethodMCVA : public HSMethod {
 public:
  HSMethodMCVA(class LAMMPS *, HSSystem &);
  ~HSMethodMCVA() override;

  int engines_supported() const override { return ENGINE_BOTH; }
  // its local form (Gauss cluster flows and pcva's ledger projection) is
  // the default, as for cva and pcva (doc "Local form")
  std::string local_limits() override;
  // the log line of init() names the form that runs
  void engine_chosen(bool local) override { local_form = local; }
  int needs_derivatives() const override { return 1; }
  void init() override;
  int modify_param(int, char **) override;
  double memory_usage() override;

  void finish_step(double tleft) override;
  bool advance_to_contact(double &tau, double tleft, const Impulse &) override;
  void begin_collisional_step() override;
  void modify_impulse(Impulse &) override;

  // local form (hs_cluster_flow.h; the counters of the flows summed over
  // the ranks at the end of each step taken by clusters)
  bool runs_cluster_flows() const override { return true; }
  void cluster_flow(HSClusterFlowJob &) override;
  void take_flow_counts(std::vector<double> &out) override;
  void add_flow_counts(const std::vector<double> &) override;
  void cluster_step_begun(HSStepView &) override;
  void cluster_step_done(HSStepView &) override;

  int nvector() const override { return 8; }
  double vector(int) override;
  std::vector<double *> counters() override;

 private:

  bool local_form = false;    // the local engine runs it (engine_chosen)
  int gauss_step = 0;    // 1 while the current step has had a predicted contact
  int cancel = 0;        // 1: the Verlet-predicted contact is replaced by an earlier one
  // counters (global, identical on all ranks)
  double gauss_iters = 0.0, gauss_substeps = 0.0, gauss_maxit = 0.0, gauss_solves = 0.0;
  double nmissed = 0.0;    // contacts of the Gauss flow the Verlet prediction missed
  double nreleased = 0.0;  // touching contacts the Gauss flow separates: no impulse
  double ncross = 0.0;     // pairs that crossed their cutoff within a Gauss sub-step
  double nlin = 0.0;       // products with the assembled G = M^-1 V'' (Newton)
  // local form: the current flow's counts, this rank's final flows' since
  // the last sum; pcva's ledger projection (hs_local_modified.h) and its
  // counts (projections done, skipped)
  double flow_counts[4] = {0.0, 0.0, 0.0, 0.0}, rank_counts[4] = {0.0, 0.0, 0.0, 0.0};
  HSLocalModified *lmod = nullptr;
  // the local form's cluster kernels and their inputs, kept from flow to
  // flow for their storage (hs_method_mcva.cpp)
  struct FlowKernel;
  std::unique_ptr<FlowKernel> fk;
  std::string held_work;
  bigint count0 = -1;
  unsigned long long idsum0 = 0;
  double nproj = 0.0, nskip = 0.0;

  // stage equations: simplified Newton (1, default) or fixed point (0);
  // fix_modify ID stages newton|fixed
  int newton = 1;
  int useG = 0;    // G assembled for the current sub-step start
  int warned_drop = 0;
  HardSphere::RadialHessian Gmat;
  HardSphere::GaussNewton2 nsolver;
  std::vector<double> gx, gy;    // G's operands in the atoms' layout
  void assemble_G();
  void count_crossings();

  // the state of a Gauss sub-step: owned group atoms idx[k], y = (q, v)
  std::vector<int> idx;
  std::vector<double> y0, f0, K1, K2, K1p, K2p, work, y1;
  double hprev = 0.0;    // step of the last solve from y0 (0: none, guess from f0)
  int f0_valid = 0;

  // per-atom fields [nmax][3] for the derivative layer
  int nmax_f = 0;
  double **fv = nullptr, **fa = nullptr, **fhv = nullptr, **ftv = nullptr, **fha = nullptr;

  void grow_fields();
  void save_start();
  void set_state(const std::vector<double> &y);
  void field(const double *y, double *k);
  void gauss_solve(double h, std::vector<double> &out);
  void gauss_substep(double h);
  double gap_of(const Impulse &, double &dg);
  int solve_contact(const Impulse &, double guess, double tmax, double &tau);
  bool find_overlap(Impulse &, Event &, int &rank);
  bool earliest_crossing(double &T, Event &, int &rank);
  void collide_missed(const Event &, int rank);
};

}    // namespace LAMMPS_NS

#endif
