/* The hydraulic four-bar driven step by step from this program: open the
 * model, set the valve's command (the model's input valve_command) from this
 * program's own function before every step, the paper's cycle that the model
 * file's table holds too, write the header and the rows `monohydra run`
 * writes, and halfway save the run's state, step on, put it back and check
 * that the steps after it come out the same to the bit. Exits 0 when every
 * call succeeded. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "monohydra/simulation.h"

static int failed(mhs_simulation* sim, const char* call, mhs_status status) {
  fprintf(stderr, "fourbar_embedded: %s returned %d: %s\n", call, (int)status, mhs_message(sim));
  return 1;
}

/* The paper's valve command (V) from step k on (t = k dt, dt = 1 ms): 10 V
 * from 1 s, 0 from 2.5 s, -10 V from 5 s, 0 from 8 s. */
static double valve_command(int64_t k) {
  if (k >= 8000) return 0.0;
  if (k >= 5000) return -10.0;
  if (k >= 2500) return 0.0;
  if (k >= 1000) return 10.0;
  return 0.0;
}

/* Writes the row of the last accepted step to `out` when the run writes one there. */
static int write_row(mhs_simulation* sim, FILE* out, char* text, size_t capacity) {
  int32_t due = 0;
  size_t length = 0;
  mhs_status st = mhs_row_due(sim, &due);
  if (st != MHS_OK) return failed(sim, "mhs_row_due", st);
  if (!due) return 0;
  st = mhs_row_text(sim, 0, text, capacity, &length);
  if (st != MHS_OK) return failed(sim, "mhs_row_text", st);
  return fwrite(text, 1, length, out) == length ? 0 : 1;
}

int main(void) {
  const char* model = "models/fourbar.yaml";
  const char* csv = "out/embedding/fourbar.csv";
  mhs_simulation* sim = NULL;
  mhs_status st = mhs_open_file(model, NULL, 0, &sim);
  if (st != MHS_OK && st != MHS_WARNING) {
    failed(sim, "mhs_open_file", st);
    mhs_free(sim);
    return 1;
  }
  if ((mkdir("out", 0777) != 0 && errno != EEXIST) ||
      (mkdir("out/embedding", 0777) != 0 && errno != EEXIST)) {
    perror("fourbar_embedded: out/embedding");
    mhs_free(sim);
    return 1;
  }
  FILE* out = fopen(csv, "w");
  if (out == NULL) {
    perror(csv);
    mhs_free(sim);
    return 1;
  }
  char text[65536];
  size_t length = 0;
  double t = 0.0, dt = 0.0, t_end = 0.0;
  int64_t k = 0;
  int rc = 0;
  uint32_t command = 0;
  double u = valve_command(0);
  if ((st = mhs_find(sim, "valve_command", &command)) != MHS_OK) rc = failed(sim, "mhs_find", st);
  if (rc == 0 && (st = mhs_set(sim, &command, 1, &u)) != MHS_OK) rc = failed(sim, "mhs_set", st);
  if (rc == 0 && (st = mhs_row_text(sim, 1, text, sizeof text, &length)) != MHS_OK)
    rc = failed(sim, "mhs_row_text", st);
  else if (rc == 0)
    fwrite(text, 1, length, out);
  if (rc == 0 && (st = mhs_start(sim)) > MHS_WARNING) rc = failed(sim, "mhs_start", st);
  if (rc == 0 && (st = mhs_time(sim, &t, NULL, &dt, &t_end)) != MHS_OK)
    rc = failed(sim, "mhs_time", st);
  if (rc == 0) rc = write_row(sim, out, text, sizeof text);

  /* Halfway: save, step 100 steps, read the boom angle; restore, step the same
   * 100 again and compare; then go on from there to the end. */
  mhs_snapshot* snapshot = NULL;
  uint32_t boom = 0;
  if (rc == 0 && (st = mhs_find(sim, "z1", &boom)) != MHS_OK) rc = failed(sim, "mhs_find", st);
  if (rc == 0 && (st = mhs_snapshot_new(sim, &snapshot)) != MHS_OK)
    rc = failed(sim, "mhs_snapshot_new", st);
  while (rc == 0 && t < t_end - 0.5 * dt) {
    /* The command for the step from t_k: held over it (a change is a jump at t_k). */
    u = valve_command(k);
    if ((st = mhs_set(sim, &command, 1, &u)) != MHS_OK) rc = failed(sim, "mhs_set", st);
    if (rc == 0 && t >= 0.5 * t_end - 0.5 * dt && t < 0.5 * t_end + 0.5 * dt) {
      double first = 0.0, second = 0.0;
      if ((st = mhs_save(sim, snapshot)) != MHS_OK) rc = failed(sim, "mhs_save", st);
      if (rc == 0 && (st = mhs_advance(sim, t + 100 * dt)) > MHS_WARNING)
        rc = failed(sim, "mhs_advance", st);
      if (rc == 0 && (st = mhs_get(sim, &boom, 1, &first)) != MHS_OK)
        rc = failed(sim, "mhs_get", st);
      if (rc == 0 && (st = mhs_restore(sim, snapshot)) != MHS_OK)
        rc = failed(sim, "mhs_restore", st);
      if (rc == 0 && (st = mhs_advance(sim, t + 100 * dt)) > MHS_WARNING)
        rc = failed(sim, "mhs_advance", st);
      if (rc == 0 && (st = mhs_get(sim, &boom, 1, &second)) != MHS_OK)
        rc = failed(sim, "mhs_get", st);
      if (rc == 0 && memcmp(&first, &second, sizeof first) != 0) {
        fprintf(stderr, "fourbar_embedded: the restored run differs (z1 %.17g, then %.17g)\n",
                first, second);
        rc = 1;
      }
      if (rc == 0 && (st = mhs_restore(sim, snapshot)) != MHS_OK)
        rc = failed(sim, "mhs_restore", st);
      if (rc == 0) printf("snapshot at t = %g s: 100 steps after it repeat to the bit\n", t);
    }
    if (rc == 0 && (st = mhs_step(sim)) > MHS_WARNING) rc = failed(sim, "mhs_step", st);
    if (rc == 0 && (st = mhs_time(sim, &t, &k, NULL, NULL)) != MHS_OK)
      rc = failed(sim, "mhs_time", st);
    if (rc == 0) rc = write_row(sim, out, text, sizeof text);
  }
  if (fclose(out) != 0) rc = 1;
  if (rc == 0) {
    double z1 = 0.0;
    if ((st = mhs_get(sim, &boom, 1, &z1)) != MHS_OK)
      rc = failed(sim, "mhs_get", st);
    else
      printf("t = %g s: z1 = %.6f rad; rows in %s\n", t, z1, csv);
  }
  mhs_snapshot_free(snapshot);
  mhs_free(sim);
  return rc;
}
