/* DEMLink.Examples.TruckLoading's exact call sequence against a real server, with
 * physical checks. The model's MultiBody part (a 50 kg bed on a vertical prismatic joint
 * with a preloaded spring-damper) is integrated here, with the particles' mean force of the
 * last interval held over the next one, as the model applies it.
 * Usage: truck_loading_sequence HOST PORT TRUCK_BED_STL
 * Prints one summary line; exit 0 when every check holds, 1 otherwise. */
#include <math.h>
#include <stdlib.h>

#include "sequence_support.h"

enum { kBox, kGravel, kGround, kSource, kTruck, kLoad, kCount };
static const char* const kNames[kCount] = {"simBox", "gravel", "ground", "source", "truck", "load"};

/* The model's parameters. */
static const double kTc = 2e-3, kStopTime = 0.8, kG = 9.81;
static const double kMass = 50.0, kStiffness = 5e4, kDamping = 2000.0; /* m [kg], c [N/m], d [N s/m] */
static const double kRate = 4.0, kStop = 0.3;                          /* source [kg/s], stopTime [s] */

int main(int argc, char** argv) {
  const double nan = dlm_not_given();
  dl_client* clients[kCount] = {NULL};
  int ok;
  int k;
  const int samples = (int)lround(kStopTime / kTc) + 1;
  double z = 0.0, v = 0.0; /* prismatic joint: s, v (the empty bed rests at s = 0) */
  double forceZ = 0.0, delivered = 0.0, loadMass = 0.0;
  int shortfall = 0, loadCount = 0, inserted = 0;
  if (argc != 4) {
    fprintf(stderr, "usage: %s HOST PORT TRUCK_BED_STL\n", argv[0]);
    return 2;
  }
  ok = sequence_connect(clients, kNames, kCount, argv[1], atoi(argv[2]), 120.0);
  if (ok) {
    const double lower[3] = {-0.4, -0.3, -0.2}, upper[3] = {0.4, 0.3, 0.6};
    const int sourceInts[1] = {2};
    const double sourceReals[16] = {kTc,  0.0, 0.0, 0.3, 0.06, 0.04, 0.03, 0.008,
                                    0.01, nan, kRate, 0.0, 0.0, -1.0, 0.0,  kStop};
    const char* sourceStrings[4] = {"particle_source", "source", "gravel", ""};
    const int truckInts[2] = {2, 1};
    const double truckReals[14] = {kTc, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.1, 0.1, 0.1};
    const char* truckStrings[4] = {"rigid_body", "truck", "gravel", argv[3]};
    const int loadInts[1] = {0};
    const double loadReals[11] = {kTc, 0.0, 0.0, 0.1, 0.3, 0.2, 0.2, 1.0, 0.0, 0.0, 0.0};
    const char* loadStrings[3] = {"region_sensor", "load", "truck"};
    ok = sequence_declare_room(clients[kBox], clients[kGravel], clients[kGround], "ground", kTc, kG, lower, upper,
                               -0.1) &&
         sequence_declare(clients[kSource], sourceInts, 1, sourceReals, 16, sourceStrings, 4) &&
         sequence_declare(clients[kTruck], truckInts, 2, truckReals, 14, truckStrings, 4) &&
         sequence_declare(clients[kLoad], loadInts, 1, loadReals, 11, loadStrings, 3);
  }
  for (k = 0; k < samples && ok; ++k) {
    const double gravity[3] = {0.0, 0.0, -kG};
    const double pose[7] = {0.0, 0.0, z, 1.0, 0.0, 0.0, 0.0}; /* frame_a: r_0 and Q reordered */
    const double twist[6] = {0.0, 0.0, v, 0.0, 0.0, 0.0};
    double boxOut[4], wrench[12], loadOut[7], masses[3];
    int particles = 0, counts[3];
    int i, pass;
    for (pass = 0; pass < kSequenceCallsPerSample && ok; ++pass) {
    ok = sequence_check_exchange(dl_simulation_box_exchange(clients[kBox], 0, gravity, boxOut, &particles),
                                 clients[kBox], "dl_simulation_box_exchange") &&
         sequence_check_exchange(dl_particle_source_read(clients[kSource], 0, counts, masses), clients[kSource],
                                 "dl_particle_source_read") &&
         sequence_check_exchange(dl_rigid_body_exchange(clients[kTruck], 0, pose, twist, wrench), clients[kTruck],
                                 "dl_rigid_body_exchange") &&
         sequence_check_exchange(dl_region_sensor_read(clients[kLoad], 0, &loadCount, loadOut), clients[kLoad],
                                 "dl_region_sensor_read");
    }
    if (!ok) break;
    inserted = counts[1];
    delivered = masses[1];
    shortfall = counts[2];
    loadMass = loadOut[0];
    forceZ = wrench[2];
    /* The model between samples: m s'' = -c s - d s' + F_z (the spring's preload carries
     * the bed's weight), F_z held; semi-implicit Euler on 20 substeps. */
    for (i = 0; i < 20; ++i) {
      const double h = kTc / 20.0;
      v += h * (-kStiffness * z - kDamping * v + forceZ) / kMass;
      z += h * v;
    }
  }
  ok = sequence_finish(clients, kCount) && ok;
  printf("truck_loading_sequence: %d samples, inserted %d particles %g kg (shortfall %d), load %d particles %g kg, "
         "force z %g N (load weight %g N), deflection %g m (force / stiffness %g m)\n",
         k, inserted, delivered, shortfall, loadCount, loadMass, forceZ, loadMass * kG, z, forceZ / kStiffness);
  fflush(stdout);
  if (!ok) return 1;
  /* A mass-rate source places whole particles: within two particle masses (r <= 10 mm) of
   * rate x duration. */
  if (!(fabs(delivered - kRate * kStop) <= 2.0 * 2650.0 * 4.0 / 3.0 * 3.14159265 * 1e-6 && shortfall == 0)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the source delivers rate x duration");
  }
  /* The load is what the source delivered (a few particles may bounce out: 5 %). */
  if (!(loadMass <= delivered * (1.0 + 1e-12) && loadMass >= 0.95 * delivered)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the truck's load equals the delivered mass");
  }
  /* At rest the bed carries the load's weight (10 %), and the spring has settled by it (5 %). */
  if (!(fabs(forceZ + loadMass * kG) <= 0.1 * loadMass * kG)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the bed carries the load's weight");
  }
  if (!(fabs(z - forceZ / kStiffness) <= 0.05 * fabs(forceZ / kStiffness))) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the suspension settles by load weight / stiffness");
  }
  return ok ? 0 : 1;
}
