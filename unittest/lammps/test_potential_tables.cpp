// The committed tables of potentials/ (potentials/README.md), read back
// through LAMMPS: two atoms at separations from contact to the cutoff,
// energy and force from LAMMPS against the model's formula and contact
// value, written out
// here again (not read from the table or from make_table.py). Tolerances:
// twice the largest interpolation error measured with pair_write on 20001
// points (README.md) for pair_style table linear 2000, and 1e-8 for spline
// 2000. Also: the first table point is sigma (1 - margin), the stock yukawa
// line of the README is the hard-core Yukawa tail to round-off, and a short
// hard-sphere run with a table does not stop at a contact.

#include "hs_test_main.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string DIR = std::string(hs_test_paths::source_dir) + "/potentials/";
const double MARGIN = 0.05;    // make_table.py's default, first point sigma (1 - MARGIN)

struct EF {
  double e, f;    // energy, radial force -dU/dr
};

struct Table {
  std::string file, keyword;
  double rc;
  std::function<EF(double)> model;    // for sigma <= r < rc (sigma = 1)
  double contact;                     // U(sigma) as README.md states it
  double tol_e, tol_f;                // linear 2000
};

// Asakura-Oosawa, kT = 1, sigma = 1; eta_p^r such that U(1) = -3 kT:
// U(1) = -eta (1 + 3/(2q)) -> eta = 3 / (1 + 1.5/q)
EF ao(double q, double r)
{
  const double eta = 3.0 / (1.0 + 1.5 / q), D = 1.0 + q;
  const double c = eta * std::pow((1.0 + q) / q, 3);
  return {-c * (1.0 - 1.5 * r / D + 0.5 * std::pow(r / D, 3)),
          -c * (1.5 / D - 1.5 * r * r / (D * D * D))};
}

// Sutherland, epsilon = sigma = 1: U = -r^-n (+ rc^-n when shifted)
EF sutherland(double n, double rc, bool shifted, double r)
{
  return {-std::pow(r, -n) + (shifted ? std::pow(rc, -n) : 0.0), -n * std::pow(r, -n - 1.0)};
}

std::vector<Table> tables()
{
  std::vector<Table> t;
  const char *aokeys[3] = {"AO_q0.1_eta0.1875_sigma1_kT1", "AO_q0.2_eta0.352941_sigma1_kT1",
                           "AO_q0.4_eta0.631579_sigma1_kT1"};
  const double qs[3] = {0.1, 0.2, 0.4};
  const char *qn[3] = {"0.1", "0.2", "0.4"};
  for (int k = 0; k < 3; k++) {
    const double q = qs[k];
    t.push_back({std::string("ao_q") + qn[k] + ".table", aokeys[k], 1.0 + q,
                 [q](double r) { return ao(q, r); }, -3.0, 1e-6, 2e-6});
  }
  const double ns[3] = {6, 12, 24}, rcs[3] = {3.0, 2.0, 1.5};
  const char *rcn[3] = {"3", "2", "1.5"};
  for (int k = 0; k < 3; k++)
    for (bool sh : {false, true}) {
      const double n = ns[k], rc = rcs[k];
      const std::string ni = std::to_string((int) n);
      t.push_back({"sutherland_n" + ni + ".table",
                   "SUTHERLAND_n" + ni + "_eps1_sigma1_rc" + rcn[k] + (sh ? "_shifted" : ""), rc,
                   [n, rc, sh](double r) { return sutherland(n, rc, sh, r); },
                   sh ? -1.0 + std::pow(rc, -n) : -1.0, 5e-5, 5e-4});
    }
  return t;
}

// separations: contact, a grid from contact to the cutoff shifted off the
// table's nodes, and just inside the cutoff
std::vector<double> separations(double rc)
{
  std::vector<double> r = {1.0};
  const int K = 37;
  for (int k = 0; k < K; k++) r.push_back(1.0 + (rc - 1.0) * (k + 0.318) / K);
  r.push_back(rc * (1.0 - 1e-9));
  return r;
}

// two atoms of type 1 on the x axis, 'pair' lines set the interaction
struct TwoAtoms {
  HSLammps L;
  explicit TwoAtoms(const std::string &pair)
  {
    L.lines(R"LMP(
units lj
atom_style atomic
atom_modify map array
boundary p p p
region box block -10 10 -10 10 -10 10 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 2 0 0 units box
mass 1 1.0
)LMP");
    L.lines(pair);
    L.lines(R"LMP(
thermo_modify norm no
variable e equal pe
variable f1 equal fx[1]
variable f2 equal fx[2]
variable f2y equal fy[2]
)LMP");
  }
  // energy, force on atom 2 along +x (= -dU/dr), force on atom 1
  void at(double r, double &e, double &f2, double &f1, double &f2y)
  {
    char buf[128];
    snprintf(buf, sizeof(buf), "set atom 2 x %.17g", r);
    L.cmd(buf);
    L.cmd("run 0 post no");
    e = L.variable("e");
    f2 = L.variable("f2");
    f1 = L.variable("f1");
    f2y = L.variable("f2y");
  }
};

void check_table(const Table &t, const std::string &style, double tol_e, double tol_f)
{
  SCOPED_TRACE(t.keyword + " " + style);
  char rc[32];
  snprintf(rc, sizeof(rc), "%.17g", t.rc);
  TwoAtoms A("pair_style table " + style + " 2000\npair_coeff 1 1 " + DIR + t.file + " " +
             t.keyword + " " + rc);
  double maxe = 0.0, maxf = 0.0;
  for (double r : separations(t.rc)) {
    double e, f2, f1, f2y;
    A.at(r, e, f2, f1, f2y);
    const EF x = t.model(r);
    EXPECT_NEAR(e, x.e, tol_e) << "r = " << r;
    EXPECT_NEAR(f2, x.f, tol_f) << "r = " << r;
    EXPECT_NEAR(f1, -f2, 1e-12 * fabs(f2)) << "r = " << r;
    EXPECT_EQ(f2y, 0.0);
    if (r == 1.0) EXPECT_NEAR(e, t.contact, tol_e) << "contact value";
    maxe = std::max(maxe, fabs(e - x.e));
    maxf = std::max(maxf, fabs(f2 - x.f));
  }
  // beyond the cutoff: no interaction
  double e, f2, f1, f2y;
  A.at(t.rc + 0.01, e, f2, f1, f2y);
  EXPECT_EQ(e, 0.0);
  EXPECT_EQ(f2, 0.0);
  printf("  %-42s %-7s max |dU| %.2e  max |dF| %.2e\n", t.keyword.c_str(), style.c_str(), maxe,
         maxf);
}

}    // namespace

TEST(PotentialTables, LinearMatchesFormula)
{
  for (const auto &t : tables()) check_table(t, "linear", t.tol_e, t.tol_f);
}

TEST(PotentialTables, SplineMatchesFormula)
{
  for (const auto &t : tables()) check_table(t, "spline", 1e-8, 1e-8);
}

// The N line of each section and its first data row: the table starts at
// sigma (1 - MARGIN), just inside contact (README: why), ends at rc.
TEST(PotentialTables, FirstPointIsContactLessMargin)
{
  for (const auto &t : tables()) {
    SCOPED_TRACE(t.keyword);
    std::ifstream in(DIR + t.file);
    ASSERT_TRUE(in.good()) << DIR + t.file;
    std::string line;
    bool found = false;
    while (std::getline(in, line)) {
      if (line != t.keyword) continue;
      found = true;
      std::getline(in, line);
      std::istringstream ns(line);
      std::string N, spacing;
      int n = 0;
      double lo = 0.0, hi = 0.0;
      ns >> N >> n >> spacing >> lo >> hi;
      EXPECT_EQ(N, "N");
      EXPECT_EQ(n, 2000);
      EXPECT_EQ(spacing, "RSQ");
      EXPECT_EQ(lo, 1.0 - MARGIN);
      EXPECT_EQ(hi, t.rc);
      std::getline(in, line);    // blank
      std::getline(in, line);
      std::istringstream rs(line);
      int i = 0;
      double r = 0.0;
      rs >> i >> r;
      EXPECT_EQ(i, 1);
      EXPECT_EQ(r, 1.0 - MARGIN);
      break;
    }
    EXPECT_TRUE(found) << "keyword " << t.keyword << " not in " << t.file;
  }
}

// README: hard-core Yukawa tail u(r) = -eps sigma exp(-kappa (r - sigma)) / r
// (u(sigma) = -eps) is pair_style yukawa's A exp(-kappa r)/r with
// A = -eps sigma exp(kappa sigma); kappa sigma = 1.8, eps = sigma = 1.
TEST(PotentialTables, YukawaHardCoreTail)
{
  const double kappa = 1.8, rc = 4.0;
  TwoAtoms A("pair_style yukawa 1.8 4.0\npair_coeff 1 1 -6.0496474644129465 4.0");
  double maxrel = 0.0;
  for (double r : separations(rc)) {
    double e, f2, f1, f2y;
    A.at(r, e, f2, f1, f2y);
    const double u = -exp(-kappa * (r - 1.0)) / r;
    const double f = -exp(-kappa * (r - 1.0)) * (kappa * r + 1.0) / (r * r);
    EXPECT_NEAR(e, u, 1e-14 * fabs(u)) << "r = " << r;
    EXPECT_NEAR(f2, f, 1e-14 * fabs(f)) << "r = " << r;
    maxrel = std::max(maxrel, std::max(fabs(e / u - 1.0), fabs(f2 / f - 1.0)));
  }
  double e, f2, f1, f2y;
  A.at(1.0, e, f2, f1, f2y);
  EXPECT_NEAR(e, -1.0, 1e-15);
  printf("  yukawa: max relative deviation %.2e\n", maxrel);
}

// A short run of an AO fluid (500 spheres, packing fraction 0.3) with
// fix hardsphere/cva and its default engine: it must not stop with
// "Pair distance < table inner cutoff" (README: the margin). In its own lmp
// process: a LAMMPS error ends the process.
TEST(PotentialTables, HardSphereRunWithTable)
{
  const std::string in = R"LMP(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.5729578
region box block 0 5 0 5 0 5
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style table linear 2000
pair_coeff 1 1 )LMP" + DIR + R"LMP(ao_q0.1.table AO_q0.1_eta0.1875_sigma1_kT1 1.1
neighbor 0.3 bin
comm_modify cutoff 1.7
velocity all create 1.0 87287 mom yes rot no dist gaussian
fix hs all hardsphere/FIXSTYLE diameter 1.0
timestep 0.005
thermo 250
run 500
)LMP";
  // pcva differentiates the table (phi'' by differences in r, backward
  // near the cutoff: the table has no values beyond it), in both engines
  // mcva continues pairs past the cutoff: a clear error instead of the
  // table's own mid-run stop
  RunResult m = run_lmp(std::regex_replace(in, std::regex("FIXSTYLE"), "mcva"));
  EXPECT_NE(m.exit_code, 0) << m.output;
  EXPECT_NE(m.output.find("Fix hardsphere/mcva cannot use pair style table"), std::string::npos)
      << m.output;
  for (const char *style : {"cva", "pcva substep local", "pcva substep global"}) {
    RunResult r = run_lmp(std::regex_replace(in, std::regex("FIXSTYLE"), style));
    EXPECT_EQ(r.exit_code, 0) << style << "\n" << r.output;
    EXPECT_EQ(r.output.find("ERROR"), std::string::npos) << style << "\n" << r.output;
    EXPECT_NE(r.output.find("Loop time"), std::string::npos) << style << "\n" << r.output;
  }
}
