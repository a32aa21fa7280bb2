/* A new process that continues a run from a snapshot's bytes:
 *   resume_snapshot MODEL FORMULATION SNAPSHOT_FILE T_END
 * opens MODEL with FORMULATION, reads the bytes, restores them, advances to
 * T_END and prints the row text of every step after the snapshot. The test
 * (snapshot_bytes_test.cpp) compares them with the rows of the process that
 * saved it. C11 against the C header alone, as an embedding program is. */
#include <stdio.h>
#include <stdlib.h>

#include "monohydra/simulation.h"

static int fail(mhs_simulation* sim, const char* call, mhs_status st) {
  fprintf(stderr, "resume_snapshot: %s returned %d: %s\n", call, (int)st, mhs_message(sim));
  mhs_free(sim);
  return 1;
}

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: resume_snapshot MODEL FORMULATION SNAPSHOT_FILE T_END\n");
    return 2;
  }
  const mhs_setting choice = {"formulation", argv[2]};
  mhs_simulation* sim = NULL;
  mhs_status st = mhs_open_file(argv[1], &choice, 1, &sim);
  if (st > MHS_WARNING) return fail(sim, "mhs_open_file", st);
  FILE* in = fopen(argv[3], "rb");
  if (in == NULL) return fail(sim, "fopen", MHS_ERROR);
  static unsigned char bytes[1 << 24];
  const size_t size = fread(bytes, 1, sizeof bytes, in);
  fclose(in);
  mhs_snapshot* snapshot = NULL;
  if ((st = mhs_snapshot_new(sim, &snapshot)) != MHS_OK) return fail(sim, "mhs_snapshot_new", st);
  if ((st = mhs_snapshot_read(sim, snapshot, bytes, size)) != MHS_OK)
    return fail(sim, "mhs_snapshot_read", st);
  if ((st = mhs_restore(sim, snapshot)) > MHS_WARNING) return fail(sim, "mhs_restore", st);
  mhs_snapshot_free(snapshot);
  const double t_end = atof(argv[4]);
  double t = 0.0, dt = 0.0;
  if ((st = mhs_time(sim, &t, NULL, &dt, NULL)) != MHS_OK) return fail(sim, "mhs_time", st);
  static char text[1 << 16];
  size_t length = 0;
  while (t < t_end - 0.5 * dt) {
    if ((st = mhs_step(sim)) > MHS_WARNING) return fail(sim, "mhs_step", st);
    if ((st = mhs_row_text(sim, 0, text, sizeof text, &length)) != MHS_OK)
      return fail(sim, "mhs_row_text", st);
    fwrite(text, 1, length, stdout);
    if ((st = mhs_time(sim, &t, NULL, NULL, NULL)) != MHS_OK) return fail(sim, "mhs_time", st);
  }
  mhs_free(sim);
  return 0;
}
