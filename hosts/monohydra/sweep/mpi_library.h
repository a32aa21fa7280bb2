/* The MPI transport's C interface: a small shared library linked to
 * OpenMPI's C API (mpi_library.c), which `monohydra sweep` loads with
 * Boost.DLL only when mpirun started it, so plain runs neither link nor load
 * libmpi. Plain C types only across the boundary. Every function returns 0 on
 * success, MPI's error code otherwise, unless said. */
#ifndef MONOHYDRA_SWEEP_MPI_LIBRARY_H
#define MONOHYDRA_SWEEP_MPI_LIBRARY_H

#ifdef __cplusplus
extern "C" {
#endif

/* MPI_Init, then this process's rank and the number of ranks. */
int mh_mpi_start(int* rank, int* size);
/* Sends `bytes` bytes to rank `dest` with `tag` (MPI_Send). */
int mh_mpi_send(int dest, int tag, const char* data, int bytes);
/* Waits up to `timeout_ms` for a message from any rank, polling with
 * MPI_Iprobe and sleeping 1 ms between polls (an idle rank does not spin a
 * core the way a blocking MPI_Recv does in OpenMPI). Returns 1 with the
 * message (*data from malloc, release it with mh_mpi_release; NUL-terminated),
 * 0 when none came, a negative value on an MPI error. */
int mh_mpi_receive(int timeout_ms, int* source, int* tag, char** data, int* bytes);
void mh_mpi_release(char* data);
/* MPI_Finalize. */
int mh_mpi_stop(void);
/* MPI_Abort of every rank (a stopped study). */
void mh_mpi_abort(int code);

#ifdef __cplusplus
}
#endif

#endif
