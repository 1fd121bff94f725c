#pragma once
// Sweeps over MPI ranks (docs/SWEEPS.md "On several machines"): `mpirun -np N edx sweep SPEC
// --db results.db`. Rank 0 owns the results database and the trace store and hands out work
// (workload points to trace first, then design points on finished traces) to one worker thread
// of its own and to ranks 1..N-1, which run serve_sweep: each asks for a task, runs it, sends the
// result back (a trace file's bytes, or a run's rows) and asks again, so the work balances
// itself. Workers never touch the database. MPI is optional at build time (EDX_HAVE_MPI); without
// it, built_with_mpi() is false and the functions below throw.
#include "arch/sweep/sweep.hpp"

namespace edx::arch {

/// Whether this edx was built with MPI.
bool built_with_mpi();
/// Whether an MPI launcher started this process (mpirun/mpiexec of OpenMPI, or Slurm's srun
/// with PMI/PMIx: OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_SIZE or PMI_RANK in the environment).
bool launched_by_mpi();

/// MPI for the life of the object (MPI_Init_thread with MPI_THREAD_FUNNELED: only the thread
/// that made it calls MPI; MPI_Finalize at the end).
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Ends every rank of the job with `code` (MPI_Abort): a failed rank 0 must not leave the
  /// workers waiting for work.
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1;
};

/// The loop of ranks 1..N-1: tasks from rank 0 until it says stop. `spec` and `options` are the
/// same as rank 0's (each rank reads the spec itself).
void serve_sweep(const SweepSpec& spec, const SweepOptions& options);

}  // namespace edx::arch
