/* DEMLink.Examples.BucketDigging's exact call sequence against a real server, with
 * physical checks. Usage: bucket_digging_sequence HOST PORT BUCKET_STL
 * (BUCKET_STL: Resources/Data/bucket.stl, what loadResource gives the model).
 * Prints one summary line; exit 0 when every check holds, 1 otherwise. */
#include <math.h>
#include <stdlib.h>

#include "sequence_support.h"

enum { kBox, kGravel, kFloor, kPit, kBucket, kFill, kPoints, kCount };
static const char* const kNames[kCount] = {"simBox", "gravel", "floor", "pit", "bucket", "fill", "points"};

/* The model's parameters. */
static const double kTc = 2e-3, kStopTime = 0.6, kT = 0.6, kX0 = -0.2, kStroke = 0.4, kZ0 = 0.11, kDepth = 0.07;
static const double kTargetHeight = 0.07; /* pit.targetHeight: the bed's top is at most this [m] */
enum { kMaxCount = 100 };                 /* points.maxCount */

int main(int argc, char** argv) {
  const double pi = 3.14159265358979323846;
  dl_client* clients[kCount] = {NULL};
  int ok;
  int k;
  const int samples = (int)lround(kStopTime / kTc) + 1; /* sample(0, tc) fires at 0, tc, ..., StopTime */
  double initialMass = 0.0, mass = 0.0, maxDrag = 0.0, maxClearForce = 0.0, fillMass = 0.0;
  int particles = 0, fillCount = 0, listed = 0, badRadius = 0;
  static double positions[3 * kMaxCount], velocities[3 * kMaxCount], radii[kMaxCount];
  static double lastPositions[3 * kMaxCount], lastVelocities[3 * kMaxCount];
  static int ids[kMaxCount], firstIds[kMaxCount];
  int firstListed = -1, idsChanged = 0, idsUnordered = 0;
  double moved = 0.0, velocityMismatch = 0.0; /* sums of |dx| and |dx - tc (v + v_last) / 2| [m] */
  if (argc != 4) {
    fprintf(stderr, "usage: %s HOST PORT BUCKET_STL\n", argv[0]);
    return 2;
  }
  ok = sequence_connect(clients, kNames, kCount, argv[1], atoi(argv[2]), 120.0);
  if (ok) { /* initial algorithms: declare in the generic layout, as the components do */
    const double lower[3] = {-1.0, -1.0, -0.05}, upper[3] = {1.0, 1.0, 0.6};
    const int pitInts[1] = {1};
    const double pitReals[10] = {0.0, -0.15, -0.07, 0.0, 0.15, 0.07, 0.1, 0.008, 0.01, kTargetHeight};
    const char* pitStrings[3] = {"pit_generator", "pit", "gravel"};
    const int bucketInts[2] = {2, 1}; /* STL from the client, PREDICTED */
    const double bucketReals[14] = {kTc, 0.0, 0.0, 0.0, kX0, 0.0, kZ0, 1.0, 0.0, 0.0, 0.0, 0.1, 0.1, 0.1};
    const char* bucketStrings[4] = {"rigid_body", "bucket", "gravel", argv[3]};
    const int fillInts[1] = {0};
    const double fillReals[11] = {kTc, 0.0, 0.0, 0.03, 0.12, 0.1, 0.06, 1.0, 0.0, 0.0, 0.0};
    const char* fillStrings[3] = {"region_sensor", "fill", "bucket"};
    const int pointsInts[1] = {kMaxCount};
    const double pointsReals[1] = {kTc};
    const char* pointsStrings[2] = {"particle_view", "points"};
    ok = sequence_declare_room(clients[kBox], clients[kGravel], clients[kFloor], "floor", kTc, 9.81, lower, upper,
                               0.0) &&
         sequence_declare(clients[kPit], pitInts, 1, pitReals, 10, pitStrings, 3) &&
         sequence_declare(clients[kBucket], bucketInts, 2, bucketReals, 14, bucketStrings, 4) &&
         sequence_declare(clients[kFill], fillInts, 1, fillReals, 11, fillStrings, 3) &&
         sequence_declare(clients[kPoints], pointsInts, 1, pointsReals, 1, pointsStrings, 2);
  }
  for (k = 0; k < samples && ok; ++k) { /* when sample(0, tc), in the model's component order */
    const double t = k * kTc;
    const double gravity[3] = {0.0, 0.0, -9.81};
    const double z = kZ0 - kDepth * sin(pi * t / kT);
    const double vz = -kDepth * pi / kT * cos(pi * t / kT);
    const double pose[7] = {kX0 + kStroke * t / kT, 0.0, z, 1.0, 0.0, 0.0, 0.0};
    const double twist[6] = {kStroke / kT, 0.0, vz, 0.0, 0.0, 0.0};
    double boxOut[4], wrench[12], fillOut[7];
    int i, pass;
    for (pass = 0; pass < kSequenceCallsPerSample && ok; ++pass) {
    ok = sequence_check_exchange(dl_simulation_box_exchange(clients[kBox], 0, gravity, boxOut, &particles),
                                 clients[kBox], "dl_simulation_box_exchange") &&
         sequence_check_exchange(dl_rigid_body_exchange(clients[kBucket], 0, pose, twist, wrench), clients[kBucket],
                                 "dl_rigid_body_exchange") &&
         sequence_check_exchange(dl_region_sensor_read(clients[kFill], 0, &fillCount, fillOut), clients[kFill],
                                 "dl_region_sensor_read") &&
         sequence_check_exchange(
             dlm_particle_view_read(clients[kPoints], 0, kMaxCount, positions, velocities, radii, ids, &listed),
             clients[kPoints], "dlm_particle_view_read");
    }
    if (!ok) break;
    if (k == 0) initialMass = boxOut[1];
    mass = boxOut[1];
    fillMass = fillOut[0];
    /* The wrench received now is the interval that begins now: the bucket moves (PREDICTED)
     * from this sample's pose with its velocity. Descending, clear of the bed: no force (on
     * the way up it carries its fill). */
    if (vz < 0.0 && z + vz * kTc > kTargetHeight + 1e-3) {
      maxClearForce = fmax(maxClearForce, fabs(wrench[0]) + fabs(wrench[1]) + fabs(wrench[2]));
    }
    maxDrag = fmax(maxDrag, -wrench[0]);
    for (i = 0; i < listed && i < kMaxCount; ++i) badRadius += radii[i] < 0.008 || radii[i] > 0.01;
    /* The bed keeps its particles (mass conserved): the same ids in every sample, and the
     * velocities integrate to the positions (trapezoid over one interval). */
    if (firstListed < 0) {
      firstListed = listed;
      for (i = 0; i < listed && i < kMaxCount; ++i) firstIds[i] = ids[i];
    } else {
      int j;
      idsChanged += listed != firstListed;
      for (i = 0; i < listed && i < firstListed && i < kMaxCount; ++i) {
        idsChanged += ids[i] != firstIds[i];
        for (j = 0; j < 3; ++j) {
          const double dx = positions[3 * i + j] - lastPositions[3 * i + j];
          moved += fabs(dx);
          velocityMismatch += fabs(dx - 0.5 * kTc * (velocities[3 * i + j] + lastVelocities[3 * i + j]));
        }
      }
    }
    for (i = 1; i < listed && i < kMaxCount; ++i) idsUnordered += ids[i] <= ids[i - 1];
    for (i = 0; i < 3 * kMaxCount; ++i) {
      lastPositions[i] = positions[i];
      lastVelocities[i] = velocities[i];
    }
  }
  ok = sequence_finish(clients, kCount) && ok;
  printf("bucket_digging_sequence: %d samples, particles %d, mass %g kg, max drag %g N, clear force %g N, "
         "fill %d particles %g kg, listed %d (ids changed %d, unordered %d; moved %g m, velocity mismatch %g m)\n",
         k, particles, mass, maxDrag, maxClearForce, fillCount, fillMass, listed, idsChanged, idsUnordered, moved,
         velocityMismatch);
  fflush(stdout);
  if (!ok) return 1;
  /* Passive earth pressure on the bucket's 100 mm wide back wall at the least depth it
   * surely reaches (bed top >= target - one diameter = 50 mm, bucket floor down to 40 mm):
   * 0.5 gamma d^2 b with K_p >= 1 and gamma = 2650 kg/m^3 x solid fraction >= 0.35 x g. */
  {
    const double dMin = (kTargetHeight - 0.02) - (kZ0 - kDepth);
    const double passive = 0.5 * 2650.0 * 0.35 * 9.81 * dMin * dMin * 0.1;
    if (maxClearForce != 0.0) ok = sequence_check(DL_ERR_INTERNAL, NULL, "no force while the bucket is clear of the bed");
    if (!(maxDrag > passive)) ok = sequence_check(DL_ERR_INTERNAL, NULL, "drag against the motion in the gravel");
  }
  if (!(fillCount > 0 && fillMass > 0.0 && fillMass < mass)) ok = sequence_check(DL_ERR_INTERNAL, NULL, "gravel in the lifted bucket");
  if (!(particles > 100 && fabs(mass - initialMass) <= 1e-9 * initialMass)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the bed's mass is conserved");
  }
  /* The view lists the particles whose id is a multiple of ceil(largest id / maxCount), a
   * subset stable across re-sorting (tested in the server's tests); the pit keeps only some
   * of the ids it generated, so here only the bounds are known: 1 to maxCount. */
  if (!(listed > 0 && listed <= kMaxCount && badRadius == 0)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "DEMPoints lists a stride-decimated subset with the pit's radii");
  }
  if (!(idsChanged == 0 && idsUnordered == 0)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "DEMPoints lists the same particles, by increasing id, at every sample");
  }
  /* The bucket stirs the listed particles; their velocities are the positions' rate (collisions
   * inside an interval make the trapezoid inexact: measured 3.3 %; zero velocities give 100 %). */
  if (!(moved > 0.0 && velocityMismatch <= 0.1 * moved)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "DEMPoints' velocities integrate to its positions");
  }
  return ok ? 0 : 1;
}
