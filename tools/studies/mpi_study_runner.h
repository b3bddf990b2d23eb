// The study runner under MPI (study_runner.h): chosen when csim was started by mpirun or srun, that is
// when the launcher's environment is there (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK). MPI is
// optional at build time (CSIM_HAVE_MPI, from find_package(MPI)): a csim built without it runs every
// study serially, and refuses to start as one of several ranks, which would each run the whole study.
#pragma once

#include "tools/studies/study_runner.h"

#include <memory>

namespace csim {

// Whether this csim was built with MPI.
bool mpi_built_in();

// Whether the environment says that a launcher started this process as one rank of a job.
bool started_by_mpi_launcher();

// The MPI runner when started by a launcher (MPI_Init_thread in its constructor, MPI_Finalize in its
// destructor: it lives as long as the command), nullptr otherwise. Throws std::runtime_error when started
// by a launcher of several ranks with MPI not built in.
std::unique_ptr<StudyRunner> make_mpi_runner(int& argc, char**& argv);

}  // namespace csim
