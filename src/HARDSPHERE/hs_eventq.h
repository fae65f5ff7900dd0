/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: kernels of event-driven hard-sphere free flight,
   used by fix hardsphere/psa (Bond & Leimkuhler 2007, section 2.1: the
   flow Psi^HS of the kinetic part H_a is pure hard-sphere motion).

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_eventq.cpp):
   - contact times on straight lines (the degree-2 case of hs_contact.h's
     gap polynomials, in closed form), with first_contact()'s conventions
     for touching, separating and overlapping pairs;
   - an event calendar: an indexed binary min-heap holding one scheduled
     event time per particle (as in Smallenburg's event-driven MD, stale
     events are dropped lazily by the caller through collision counters).
------------------------------------------------------------------------- */

#ifndef LMP_HS_EVENTQ_H
#define LMP_HS_EVENTQ_H

#include "hs_contact.h"

#include <cmath>
#include <vector>

namespace HardSphere {

// Earliest approaching contact of two spheres in free flight,
// g(t) = |dq + t dv|^2 - sigma^2 = c0 + 2 b t + a t^2, on (0, tmax].
// Same conventions as first_contact(c, 2, tmax, tol): c0 < -tol is an
// OVERLAP; |c0| <= tol is touching: CONTACT_NOW if approaching (b < 0),
// else the gap is measured from the contact and a separating straight line
// never returns. Otherwise the smaller root of the quadratic, in the
// cancellation-free form t = c0 / (-b + sqrt(D)), D = b^2 - a c0; a tangent
// line (D == 0) only grazes and is no contact. D is evaluated as
// a sigma^2 - |dq x dv|^2 (Lagrange's identity), which near grazing cancels
// only numbers of size a sigma^2 instead of b^2 ~ a |dq|^2.
inline Contact free_flight_pair_contact(const double *dq, const double *dv, double sigma,
                                        double tmax, double tol)
{
  const double c0 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2] - sigma * sigma;
  const double b = dq[0] * dv[0] + dq[1] * dv[1] + dq[2] * dv[2];
  if (c0 < -tol) return {OVERLAP, 0.0};
  if (c0 <= tol) return (b < 0.0) ? Contact{CONTACT_NOW, 0.0} : Contact{NO_CONTACT, 0.0};
  if (!(b < 0.0)) return {NO_CONTACT, 0.0};
  const double a = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
  // still apart at tmax while closing all the way (vertex -b/a >= tmax):
  // the common case of a far pair, decided without a square root
  if (-b >= a * tmax && c0 + tmax * (2.0 * b + a * tmax) > 0.0) return {NO_CONTACT, 0.0};
  const double cx = dq[1] * dv[2] - dq[2] * dv[1], cy = dq[2] * dv[0] - dq[0] * dv[2],
               cz = dq[0] * dv[1] - dq[1] * dv[0];
  const double disc = a * sigma * sigma - (cx * cx + cy * cy + cz * cz);
  if (!(disc > 0.0)) return {NO_CONTACT, 0.0};
  const double t = c0 / (-b + std::sqrt(disc));
  if (!(t <= tmax)) return {NO_CONTACT, 0.0};
  return {CONTACT, t};
}

// Sphere and plane in free flight: g(t) = dist + t vn (dist = centre
// distance from the plane minus the radius, vn = velocity along the
// plane's inward normal). Same conventions as above.
inline Contact free_flight_wall_contact(double dist, double vn, double tmax, double tol)
{
  if (dist < -tol) return {OVERLAP, 0.0};
  if (dist <= tol) return (vn < 0.0) ? Contact{CONTACT_NOW, 0.0} : Contact{NO_CONTACT, 0.0};
  if (!(vn < 0.0)) return {NO_CONTACT, 0.0};
  const double t = dist / -vn;
  if (!(t <= tmax)) return {NO_CONTACT, 0.0};
  return {CONTACT, t};
}

// Indexed binary min-heap over slots 0..n-1: each slot holds at most one
// key (its particle's next event time). set() inserts or moves a slot,
// remove() takes it out, both O(log n); top() is the slot with the
// smallest key. Ties go to whichever the heap holds on top (callers that
// need a deterministic order break ties themselves).
class EventHeap {
 public:
  // n empty slots; O(n)
  void reset(int n)
  {
    pos_.assign(n, -1);
    key_.resize(n);
    heap_.clear();
  }
  int size() const { return (int) heap_.size(); }
  bool empty() const { return heap_.empty(); }
  bool contains(int k) const { return pos_[k] >= 0; }
  int top() const { return heap_[0]; }
  double top_key() const { return key_[heap_[0]]; }
  double key(int k) const { return key_[k]; }

  void set(int k, double t)
  {
    if (pos_[k] < 0) {
      key_[k] = t;
      pos_[k] = (int) heap_.size();
      heap_.push_back(k);
      up(pos_[k]);
    } else {
      const double old = key_[k];
      key_[k] = t;
      if (t < old) up(pos_[k]);
      else down(pos_[k]);
    }
  }

  void remove(int k)
  {
    const int p = pos_[k];
    if (p < 0) return;
    const int last = heap_.back();
    heap_.pop_back();
    pos_[k] = -1;
    if (last == k) return;
    heap_[p] = last;
    pos_[last] = p;
    up(p);
    down(pos_[last]);
  }

 private:
  std::vector<int> heap_;       // slots in heap order
  std::vector<int> pos_;        // pos_[k] = index of slot k in heap_, -1 if absent
  std::vector<double> key_;

  void up(int p)
  {
    const int k = heap_[p];
    const double t = key_[k];
    while (p > 0) {
      const int parent = (p - 1) >> 1;
      const int kp = heap_[parent];
      if (!(t < key_[kp])) break;
      heap_[p] = kp;
      pos_[kp] = p;
      p = parent;
    }
    heap_[p] = k;
    pos_[k] = p;
  }

  void down(int p)
  {
    const int n = (int) heap_.size();
    const int k = heap_[p];
    const double t = key_[k];
    while (true) {
      int c = 2 * p + 1;
      if (c >= n) break;
      if (c + 1 < n && key_[heap_[c + 1]] < key_[heap_[c]]) ++c;
      const int kc = heap_[c];
      if (!(key_[kc] < t)) break;
      heap_[p] = kc;
      pos_[kc] = p;
      p = c;
    }
    heap_[p] = k;
    pos_[k] = p;
  }
};

}    // namespace HardSphere

#endif
