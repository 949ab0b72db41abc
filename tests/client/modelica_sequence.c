/* A Modelica-style call sequence through the typed declarations, in C (the package's own
 * examples, which declare in the generic layout, are replayed by tests/modelica):
 *   - construction of each component's ExternalObject: dl_client_create and
 *     dl_set_exchange_order(DL_ORDER_SEND_FIRST_SPLIT), as dlm_client_connect does
 *   - initial algorithm of each component: dl_connect_to_host, dl_declare_<kind>
 *   - each sample(0, tc) event: the due components' dl_<kind>_exchange / _read, in
 *     declaration order, twice: the first pass sends the inputs at t, the second (the
 *     event iteration after it) returns the outputs of [t, t + tc]
 *   - terminal(): dl_finish for every component; then the destructors dl_client_destroy.
 * One client (connection) per component, all driven from this one thread, as a Modelica
 * tool does. Usage: modelica_sequence HOST PORT [SAMPLES] [fake]
 * With "fake" the outputs are checked against the test fake server's encoding.
 * Exits 0 on success, 1 with the error message on any failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demlink/demlink_c.h"

enum { kBox, kMaterial, kBody, kSensor, kSource, kCount };
static const char* const kNames[kCount] = {"simBox", "gravel", "bucket", "bucketFill", "feeder"};

static int check(int status, dl_client* client, const char* what) {
  if (status != DL_OK) {
    fprintf(stderr, "modelica_sequence: %s failed (status %d, server code %d): %s\n", what, status,
            client != NULL ? dl_last_server_error_code(client) : 0,
            client != NULL ? dl_last_error(client) : "no client");
    return 0;
  }
  return 1;
}

int main(int argc, char** argv) {
  const char* host;
  int port;
  int samples = 20;
  int fake = 0;
  const double tc = 0.002;          /* SimulationBox.tc [s] */
  const double sensorTc = 2.0 * tc; /* the sensor samples every second event [s] */
  dl_client* clients[kCount] = {NULL, NULL, NULL, NULL, NULL};
  int handles[kCount] = {-1, -1, -1, -1, -1};
  int ok = 1;
  int i;
  int k;

  if (argc < 3) {
    fprintf(stderr, "usage: %s HOST PORT [SAMPLES] [fake]\n", argv[0]);
    return 2;
  }
  host = argv[1];
  port = atoi(argv[2]);
  if (argc > 3) samples = atoi(argv[3]);
  if (argc > 4 && strcmp(argv[4], "fake") == 0) fake = 1;

  /* ExternalObject constructors. */
  for (i = 0; i < kCount; ++i) {
    clients[i] = dl_client_create();
    if (clients[i] == NULL) {
      fprintf(stderr, "modelica_sequence: out of memory\n");
      return 1;
    }
    if (!check(dl_set_exchange_order(clients[i], DL_ORDER_SEND_FIRST_SPLIT), clients[i], "dl_set_exchange_order")) {
      return 1;
    }
  }

  /* initial algorithm of every component: connect and declare (no waiting for Compiled).
   * The box's end time is the experiment's stop time (samples x tc), as the Modelica model
   * passes it: with a later end time the real server would go on simulating to it after the
   * last exchanged component said Bye, while a Bye of a non-exchanged one is still in flight. */
  {
    const double gravity[3] = {0.0, 0.0, -9.81};
    const double lower[3] = {-2.0, -2.0, -1.0};
    const double upper[3] = {2.0, 2.0, 3.0};
    const double size[3] = {1.0, 0.6, 0.4};
    const double pose[7] = {0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0};
    const double sensorCentre[3] = {0.0, 0.0, 0.0};
    const double sensorSize[3] = {0.9, 0.5, 0.35};
    const double sourceCentre[3] = {0.0, 0.0, 1.5};
    const double sourceHalf[3] = {0.3, 0.3, 0.1};
    const double sourceVelocity[3] = {0.0, 0.0, -1.0};
    for (i = 0; i < kCount && ok; ++i) {
      ok = check(dl_connect_to_host(clients[i], host, port, kNames[i], ""), clients[i], "dl_connect_to_host");
    }
    ok = ok && check(dl_declare_simulation_box(clients[kBox], kNames[kBox], tc, 1e-5, samples * tc, gravity, lower,
                                               upper, kCount, &handles[kBox]),
                     clients[kBox], "dl_declare_simulation_box");
    ok = ok && check(dl_declare_material(clients[kMaterial], kNames[kMaterial], "gravel", -1, -1, -1, -1, -1, -1,
                                         &handles[kMaterial]),
                     clients[kMaterial], "dl_declare_material");
    ok = ok && check(dl_declare_rigid_body_box(clients[kBody], kNames[kBody], tc, size, "gravel", pose, 1,
                                               &handles[kBody]),
                     clients[kBody], "dl_declare_rigid_body_box");
    ok = ok && check(dl_declare_region_sensor_box(clients[kSensor], kNames[kSensor], sensorTc, sensorCentre,
                                                  sensorSize, kNames[kBody], &handles[kSensor]),
                     clients[kSensor], "dl_declare_region_sensor_box");
    ok = ok && check(dl_declare_particle_source_box(clients[kSource], kNames[kSource], tc, "gravel", sourceCentre,
                                                    sourceHalf, 0.01, 0.015, 2000.0, -1.0, sourceVelocity, 7,
                                                    &handles[kSource]),
                     clients[kSource], "dl_declare_particle_source_box");
  }

  /* when sample(0, tc): every component whose sample fires, in declaration order. */
  for (k = 0; k < samples && ok; ++k) {
    const double t = k * tc;
    double boxOut[4];
    int particleCount = 0;
    double pose[7] = {0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0};
    const double twist[6] = {0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
    double wrench[12];
    int counts[3];
    double masses[3];
    int pass;
    pose[0] = 0.1 * t; /* the bucket moves along x at 0.1 m/s */

    for (pass = 0; pass < 2 && ok; ++pass) {
    ok = check(dl_simulation_box_exchange(clients[kBox], handles[kBox], NULL, boxOut, &particleCount), clients[kBox],
               "dl_simulation_box_exchange");
    ok = ok && check(dl_rigid_body_exchange(clients[kBody], handles[kBody], pose, twist, wrench), clients[kBody],
                     "dl_rigid_body_exchange");
    if (ok && k % 2 == 0) {
      int count = 0;
      double sensorOut[7];
      ok = check(dl_region_sensor_read(clients[kSensor], handles[kSensor], &count, sensorOut), clients[kSensor],
                 "dl_region_sensor_read");
      /* fake server: count = step * 10 + id (id < 10). The sensor's interval is two
       * samples: its answer arrives while the others step on, and the first call of its
       * next sample receives it, so at sample k it holds [k - 2, k] (step 2 k) */
      if (ok && fake && count / 10 != 2 * k) {
        fprintf(stderr, "modelica_sequence: sensor count %d at sample %d\n", count, k);
        ok = 0;
      }
    }
    ok = ok && check(dl_particle_source_read(clients[kSource], handles[kSource], counts, masses), clients[kSource],
                     "dl_particle_source_read");
    }
    /* fake server: the outputs of the interval that begins now (ending at step 2 k + 2) */
    if (ok && fake && (fabs(wrench[0] - 2.0 * (k + 1)) > 0.0 || counts[1] != 3 * 2 * (k + 1))) {
      fprintf(stderr, "modelica_sequence: sample %d got mean force x %g, inserted total %d\n", k, wrench[0],
              counts[1]);
      ok = 0;
    }
    if (ok && k == samples - 1) {
      printf("modelica_sequence: %d samples, t = %g s, particles %d, mean force (%g, %g, %g) N\n", samples, t,
             particleCount, wrench[0], wrench[1], wrench[2]);
    }
  }

  /* terminal(): Bye from every component (without waiting), then the destructors. */
  for (i = 0; i < kCount; ++i) {
    if (dl_finish(clients[i], "terminal()") != DL_OK && ok) {
      fprintf(stderr, "modelica_sequence: dl_finish failed: %s\n", dl_last_error(clients[i]));
      ok = 0;
    }
  }
  for (i = 0; i < kCount; ++i) dl_client_destroy(clients[i]);
  return ok ? 0 : 1;
}
