/* The MPI transport library (mpi_library.h): OpenMPI's C API behind six
 * plain-C functions. */
#include "mpi_library.h"

#include <mpi.h>
#include <stdlib.h>
#include <time.h>

#define MH_EXPORT __attribute__((visibility("default")))

MH_EXPORT int mh_mpi_start(int* rank, int* size) {
  int code = MPI_Init(NULL, NULL);
  if (code != MPI_SUCCESS) return code;
  code = MPI_Comm_rank(MPI_COMM_WORLD, rank);
  if (code != MPI_SUCCESS) return code;
  return MPI_Comm_size(MPI_COMM_WORLD, size);
}

MH_EXPORT int mh_mpi_send(int dest, int tag, const char* data, int bytes) {
  return MPI_Send(data, bytes, MPI_CHAR, dest, tag, MPI_COMM_WORLD);
}

MH_EXPORT int mh_mpi_receive(int timeout_ms, int* source, int* tag, char** data, int* bytes) {
  const struct timespec pause = {0, 1000000};
  for (int waited = 0;; ++waited) {
    int flag = 0;
    MPI_Status status;
    if (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status) != MPI_SUCCESS)
      return -1;
    if (flag) {
      int count = 0;
      MPI_Get_count(&status, MPI_CHAR, &count);
      char* buffer = malloc((size_t)count + 1);
      if (buffer == NULL) return -1;
      if (MPI_Recv(buffer, count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE) != MPI_SUCCESS) {
        free(buffer);
        return -1;
      }
      buffer[count] = '\0';
      *source = status.MPI_SOURCE;
      *tag = status.MPI_TAG;
      *data = buffer;
      *bytes = count;
      return 1;
    }
    if (waited >= timeout_ms) return 0;
    nanosleep(&pause, NULL);
  }
}

MH_EXPORT void mh_mpi_release(char* data) {
  free(data);
}

MH_EXPORT int mh_mpi_stop(void) {
  return MPI_Finalize();
}

MH_EXPORT void mh_mpi_abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
}
