/* ----------------------------------------------------------------------
   lmp: LAMMPS driver with the HARDSPHERE styles registered.

   LAMMPS' own src/main.cpp of the version we compile against (29Sep2021,
   or 4Feb2025 with its exception handlers, selected by CMake's
   HS_LAMMPS_ALWAYS_EXCEPTIONS), plus one call to
   hardsphere_register_styles() after the LAMMPS instance is created.
   All usual command-line options (-in, -var, -log, -screen, -echo, ...)
   are parsed by LAMMPS itself.

   NOTE: the input command "clear" re-creates Modify and drops the
   HARDSPHERE styles (see hardsphere_registry.h).
------------------------------------------------------------------------- */

#include "lammps.h"

#include "accelerator_kokkos.h"
#include "input.h"
#include "library.h"
#include "lmppython.h"

#include "hardsphere_registry.h"

#if defined(LAMMPS_EXCEPTIONS) || (defined(HS_LAMMPS_ALWAYS_EXCEPTIONS) && HS_LAMMPS_ALWAYS_EXCEPTIONS)
#include "exceptions.h"
#endif

#include "fmt/format.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <mpi.h>
#include <new>

using namespace LAMMPS_NS;

#if defined(HS_LAMMPS_ALWAYS_EXCEPTIONS) && HS_LAMMPS_ALWAYS_EXCEPTIONS

// LAMMPS >= 2023: errors are always C++ exceptions; this is the main() of
// LAMMPS 4Feb2025 (src/main.cpp), without MDI and FPE trapping
static void finalize()
{
  lammps_kokkos_finalize();
  lammps_python_finalize();
}

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  MPI_Comm lammps_comm = MPI_COMM_WORLD;

  try {
    auto lmp = new LAMMPS(argc, argv, lammps_comm);
    hardsphere_register_styles(lmp);
    lmp->input->file();
    delete lmp;
  } catch (LAMMPSAbortException &ae) {
    finalize();
    MPI_Abort(ae.get_universe(), 1);
  } catch (LAMMPSException &) {
    finalize();
    MPI_Barrier(lammps_comm);
    MPI_Finalize();
    exit(1);
  } catch (fmt::format_error &fe) {
    fprintf(stderr, "fmt::format_error: %s\n", fe.what());
    finalize();
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
  } catch (std::bad_alloc &ae) {
    fprintf(stderr, "C++ memory allocation failed: %s\n", ae.what());
    finalize();
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
  } catch (std::exception &e) {
    fprintf(stderr, "Exception: %s\n", e.what());
    finalize();
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
  }
  finalize();
  MPI_Barrier(lammps_comm);
  MPI_Finalize();
  return 0;
}

#else

// LAMMPS 29Sep2021: the main() of that version (exceptions optional)
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

#endif
