/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the one variable-length gather the local engine, its
   restricted forces and pcva's local projection each need: every rank's
   vector, concatenated in rank order, on every rank (MPI_Allgather of the
   sizes, then MPI_Allgatherv). LAMMPS-free.
------------------------------------------------------------------------- */

#ifndef LMP_HS_MPI_H
#define LMP_HS_MPI_H

#include <mpi.h>
#include <vector>

namespace HardSphere {

template <class T>
void allgatherv(MPI_Comm comm, MPI_Datatype type, const std::vector<T> &mine, std::vector<T> &all)
{
  int nprocs = 1;
  MPI_Comm_size(comm, &nprocs);
  if (nprocs == 1) {
    all = mine;
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
