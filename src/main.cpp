/* ----------------------------------------------------------------------
   lmp: LAMMPS driver with the HARDSPHERE styles registered.

   Identical to LAMMPS' own src/main.cpp, plus one call to
   hardsphere_register_styles() after the LAMMPS instance is created.
   All usual command-line options (-in, -var, -log, -screen, -echo, ...)
   are parsed by LAMMPS itself.

   NOTE: the input command "clear" re-creates Modify and drops the
   HARDSPHERE styles (see hardsphere_registry.h).
------------------------------------------------------------------------- */

#include "lammps.h"

#include "accelerator_kokkos.h"
#include "input.h"
#include "lmppython.h"

#include "hardsphere_registry.h"

#if defined(LAMMPS_EXCEPTIONS)
#include "exceptions.h"
#endif

#include "fmt/format.h"

#include <cstdio>
#include <cstdlib>
#include <mpi.h>

using namespace LAMMPS_NS;

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);

  MPI_Comm lammps_comm = MPI_COMM_WORLD;

#ifdef LAMMPS_EXCEPTIONS
  try {
    auto lmp = new LAMMPS(argc, argv, lammps_comm);
    hardsphere_register_styles(lmp);
    lmp->input->file();
    delete lmp;
  } catch (LAMMPSAbortException &ae) {
    KokkosLMP::finalize();
    Python::finalize();
    MPI_Abort(ae.universe, 1);
  } catch (LAMMPSException &e) {
    KokkosLMP::finalize();
    Python::finalize();
    MPI_Barrier(lammps_comm);
    MPI_Finalize();
    exit(1);
  } catch (fmt::format_error &fe) {
    fprintf(stderr, "fmt::format_error: %s\n", fe.what());
    KokkosLMP::finalize();
    Python::finalize();
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
  }
#else
  try {
    auto lmp = new LAMMPS(argc, argv, lammps_comm);
    hardsphere_register_styles(lmp);
    lmp->input->file();
    delete lmp;
  } catch (fmt::format_error &fe) {
    fprintf(stderr, "fmt::format_error: %s\n", fe.what());
    KokkosLMP::finalize();
    Python::finalize();
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
  }
#endif
  KokkosLMP::finalize();
  Python::finalize();
  MPI_Barrier(lammps_comm);
  MPI_Finalize();
  return 0;
}
