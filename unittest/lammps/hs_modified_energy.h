/* -*- c++ -*- ----------------------------------------------------------
   Test helper: an independent evaluation of the modified Hamiltonian
   H_[2,VV] = H + dt^2/24 (2 v^T V'' v - grad V^T M^-1 grad V)
   (Bond & Leimkuhler 2007, section 3) for systems of harmonic bonds
   V = sum K (r - r0)^2 (LAMMPS bond_style harmonic), written out by hand
   from positions and velocities read from a text dump. Atoms outside the
   integrated group count as fixed (no kinetic energy, no derivatives).
   Unit factors (mvv2e, ftm2v) are passed in by the test from the LAMMPS
   units documentation, not taken from the code under test.
------------------------------------------------------------------------- */

#ifndef HS_MODIFIED_ENERGY_H
#define HS_MODIFIED_ENERGY_H

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hs_test {

struct HarmonicBond {
  int a, b;    // atom IDs
  double K, r0;
};

struct AtomState {
  double x[3], v[3];
};

// one snapshot per dump frame: step and atom ID -> state
struct Frame {
  long step;
  std::map<int, AtomState> atoms;
};

// dump custom with columns "id x y z vx vy vz" (any float format)
inline std::vector<Frame> read_dump(const std::string &path)
{
  std::vector<Frame> frames;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: TIMESTEP", 0) == 0) {
      Frame fr;
      std::getline(in, line);
      fr.step = std::stol(line);
      std::getline(in, line);    // ITEM: NUMBER OF ATOMS
      std::getline(in, line);
      const int n = std::stoi(line);
      for (int k = 0; k < 4; k++) std::getline(in, line);    // box
      std::getline(in, line);                                // ITEM: ATOMS ...
      for (int k = 0; k < n; k++) {
        std::getline(in, line);
        std::istringstream ls(line);
        int id;
        AtomState s;
        ls >> id >> s.x[0] >> s.x[1] >> s.x[2] >> s.v[0] >> s.v[1] >> s.v[2];
        fr.atoms[id] = s;
      }
      frames.push_back(fr);
    }
  }
  return frames;
}

struct ModifiedEnergy {
  double H;     // 1/2 p M^-1 p + V
  double Ht;    // H_[2,VV]
};

// masses: ID -> mass for atoms of the group (others are fixed)
inline ModifiedEnergy modified_energy(const Frame &fr, const std::vector<HarmonicBond> &bonds,
                                      const std::map<int, double> &masses, double dt,
                                      double mvv2e, double ftm2v)
{
  std::map<int, std::array<double, 3>> grad;
  double kin = 0.0, V = 0.0, vhv = 0.0, g2 = 0.0;
  auto vel = [&](int id, int k) { return masses.count(id) ? fr.atoms.at(id).v[k] : 0.0; };
  for (const auto &[id, m] : masses) {
    const AtomState &s = fr.atoms.at(id);
    kin += 0.5 * m * (s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]) * mvv2e;
    grad[id] = {0.0, 0.0, 0.0};
  }
  for (const HarmonicBond &b : bonds) {
    const AtomState &A = fr.atoms.at(b.a), &B = fr.atoms.at(b.b);
    double d[3], w[3];
    for (int k = 0; k < 3; k++) {
      d[k] = A.x[k] - B.x[k];
      w[k] = vel(b.a, k) - vel(b.b, k);
    }
    const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double n[3] = {d[0] / r, d[1] / r, d[2] / r};
    V += b.K * (r - b.r0) * (r - b.r0);
    // V'' of K (r - r0)^2 in d: 2K [n n^T + (r - r0)/r (I - n n^T)]
    const double nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    vhv += 2.0 * b.K * (nw * nw + (r - b.r0) / r * (ww - nw * nw));
    for (int k = 0; k < 3; k++) {
      const double g = 2.0 * b.K * (r - b.r0) * n[k];
      if (grad.count(b.a)) grad[b.a][k] += g;
      if (grad.count(b.b)) grad[b.b][k] -= g;
    }
  }
  for (const auto &[id, g] : grad) g2 += (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) / masses.at(id);
  ModifiedEnergy e;
  e.H = kin + V;
  e.Ht = e.H + dt * dt / 12.0 * vhv - dt * dt / 24.0 * g2 * ftm2v;
  return e;
}

// per-step values of a fix ave/time file (lines "step value ...")
inline std::map<long, std::vector<double>> read_series(const std::string &path)
{
  std::map<long, std::vector<double>> s;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    long step;
    ls >> step;
    double x;
    while (ls >> x) s[step].push_back(x);
  }
  return s;
}

}    // namespace hs_test

#endif
