/* One run of a model through the embedding API, as `monohydra run MODEL
 * --formulation F --t-end T` runs it: every row due written as text (to
 * /dev/null), so that bench/embedded_instructions_per_step.sh counts the
 * same work on both sides.
 *   mh_embedded_run MODEL FORMULATION T_END ROW_EVERY_STEPS */
#include <stdio.h>
#include <stdlib.h>

#include "monohydra/simulation.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: mh_embedded_run MODEL FORMULATION T_END ROW_EVERY_STEPS\n");
    return 2;
  }
  const mhs_setting settings[] = {{"formulation", argv[2]}, {"t_end", argv[3]}};
  const long every = atol(argv[4]);
  mhs_simulation* sim = NULL;
  mhs_status st = mhs_open_file(argv[1], settings, 2, &sim);
  FILE* out = fopen("/dev/null", "w");
  static char row[1 << 16];
  size_t length = 0;
  double t = 0.0, dt = 0.0, t_end = 0.0;
  int64_t steps = 0;
  if (st <= MHS_WARNING) st = mhs_row_text(sim, 1, row, sizeof row, &length);
  if (st <= MHS_WARNING) fwrite(row, 1, length, out);
  if (st <= MHS_WARNING) st = mhs_start(sim);
  if (st <= MHS_WARNING) st = mhs_time(sim, &t, NULL, &dt, &t_end);
  while (st <= MHS_WARNING) {
    if (steps % every == 0 && (st = mhs_row_text(sim, 0, row, sizeof row, &length)) == MHS_OK)
      fwrite(row, 1, length, out);
    if (t >= t_end - 0.5 * dt) break;
    if (st <= MHS_WARNING) st = mhs_step(sim);
    if (st <= MHS_WARNING) st = mhs_time(sim, &t, &steps, NULL, NULL);
  }
  if (st > MHS_WARNING) fprintf(stderr, "mh_embedded_run: %s\n", mhs_message(sim));
  fclose(out);
  mhs_free(sim);
  return st > MHS_WARNING;
}
