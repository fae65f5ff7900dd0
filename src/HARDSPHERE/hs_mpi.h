/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the one variable-length gather the local engine, its
   restricted forces and pcva's local projection each need: every rank's
   vector, concatenated in rank order, on every rank (MPI_Allgather of the
   sizes, then MPI_Allgatherv). LAMMPS-free.
------------------------------------------------------------------------- */

#ifndef LMP_HS_MPI_H
#define LMP_HS_MPI_H

#include <memory>
#include <mpi.h>
#include <utility>
#include <vector>

namespace HardSphere {

// an allocator whose resize() leaves new elements uninitialised: a gather
// buffer that alternates between small and large gathers is otherwise
// zero-filled again on every growth (0.3 % of a 2-rank step at 256000
// atoms), only to be overwritten by MPI
template <class T> struct NoInitAllocator : std::allocator<T> {
  template <class U> struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <class U> NoInitAllocator(const NoInitAllocator<U> &) {}
  template <class U> void construct(U *p) { ::new (static_cast<void *>(p)) U; }
  template <class U, class... Args> void construct(U *p, Args &&...args)
  {
    ::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T> using GatherBuffer = std::vector<T, NoInitAllocator<T>>;

template <class T, class A1, class A2>
void allgatherv(MPI_Comm comm, MPI_Datatype type, const std::vector<T, A1> &mine,
                std::vector<T, A2> &all)
{
  int nprocs = 1;
  MPI_Comm_size(comm, &nprocs);
  if (nprocs == 1) {
    all.assign(mine.begin(), mine.end());
    return;
  }
  int n = (int) mine.size();
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  all.resize(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), n, type, all.data(), counts.data(), displs.data(), type, comm);
}

}    // namespace HardSphere

#endif
