/* DEMLink.Examples.SwitchedSourceAndSink's exact call sequence against a real server, with
 * physical checks of the run-time inputs: the source's rate steps from 4 to 8 kg/s at
 * sample 50 (0.1 s) and the source is switched off at sample 100, the sensor gets the
 * floor's volume at sample 0 and is moved onto the floor at sample 250, the sink (off from
 * sample 0) is switched on at sample 300. Each component sends a change of its inputs
 * before its read, as the model's when-clauses do (only when the input changed). The
 * initialisation runs twice (a tool may repeat it).
 * Usage: switched_source_sequence HOST PORT
 * Prints one summary line; exit 0 when every check holds, 1 otherwise. */
#include <math.h>
#include <stdlib.h>

#include "sequence_support.h"

enum { kBox, kGravel, kGround, kSource, kSink, kPile, kCount };
static const char* const kNames[kCount] = {"simBox", "gravel", "ground", "source", "sink", "pile"};

/* The model's parameters and input switching samples. */
static const double kTc = 2e-3, kStopTime = 0.8, kG = 9.81;
enum { kRateStep = 50, kGateOff = 100, kPileMove = 250, kSinkOn = 300 };
static const double kRateLow = 4.0, kRateHigh = 8.0; /* [kg/s] */
static const double kParticleMassMax = 2650.0 * 4.0 / 3.0 * 3.14159265358979 * 1e-6; /* r = 10 mm [kg] */

int main(int argc, char** argv) {
  const double nan = dlm_not_given();
  dl_client* clients[kCount] = {NULL};
  int ok;
  int k;
  const int samples = (int)lround(kStopTime / kTc) + 1;
  double delivered = 0.0, deliveredAtGate = -1.0, deliveredBeforeGate = -1.0, deliveredAtGateMinus = -1.0;
  double pileBeforeMove = -1.0, pileBeforeSink = -1.0, worldBeforeSink = -1.0, removedBeforeSink = -1.0;
  double worldMass = 0.0, removed = 0.0, pileMass = 0.0;
  int shortfall = 0, pileCount = 0, particles = 0;
  if (argc != 3) {
    fprintf(stderr, "usage: %s HOST PORT\n", argv[0]);
    return 2;
  }
  ok = sequence_connect(clients, kNames, kCount, argv[1], atoi(argv[2]), 120.0);
  if (ok) {
    const double lower[3] = {-0.5, -0.4, -0.1}, upper[3] = {0.5, 0.4, 0.6};
    /* seed, Box, Uniform; centre, half extents, r_min, r_max, rates, velocity, start,
     * stop, disc radius, thickness, linear weights (ParticleSource.declReals). */
    const int sourceInts[3] = {2, 0, 1};
    const double sourceReals[20] = {kTc,  0.0, 0.0,      0.3,  0.1, 0.06, 0.04, 0.008, 0.01, nan,
                                    kRateLow, 0.0, 0.0, -1.0, 0.0,  nan,  0.2,  0.0,   1.0,  1.0};
    const char* sourceStrings[4] = {"particle_source", "source", "gravel", ""};
    const int regionInts[1] = {0};
    const double sinkReals[11] = {kTc, 0.0, 0.0, 0.1, 0.8, 0.6, 0.2, 1.0, 0.0, 0.0, 0.0};
    const char* sinkStrings[3] = {"particle_sink", "sink", ""};
    const double pileReals[11] = {kTc, 0.0, 0.0, 0.45, 0.1, 0.1, 0.1, 1.0, 0.0, 0.0, 0.0};
    const char* pileStrings[3] = {"region_sensor", "pile", ""};
    int pass;
    /* The initial algorithms twice, as a tool may repeat the initialisation: the second
     * connect, the identical declarations and DeclarationsDone change nothing (the first
     * pass's last DeclarationsDone has started the compile). */
    for (pass = 0; pass < 2 && ok; ++pass) {
      ok = sequence_declare_room(clients[kBox], clients[kGravel], clients[kGround], "ground", kTc, kG, lower, upper,
                                 0.0) &&
           sequence_declare(clients[kSource], sourceInts, 3, sourceReals, 20, sourceStrings, 4) &&
           sequence_declare(clients[kSink], regionInts, 1, sinkReals, 11, sinkStrings, 3) &&
           sequence_declare(clients[kPile], regionInts, 1, pileReals, 11, pileStrings, 3);
    }
  }
  for (k = 0; k < samples && ok; ++k) {
    const double gravity[3] = {0.0, 0.0, -kG};
    const double orientation[4] = {1.0, 0.0, 0.0, 0.0};
    const double pileSize[3] = {0.8, 0.6, 0.2};
    const double pileCentre[3] = {0.0, 0.0, k >= kPileMove ? 0.1 : 0.45};
    double boxOut[4], sourceMasses[3], sinkMasses[2], pileOut[7];
    int sourceCounts[3], sinkCounts[2];
    int pass;
    /* The run-time inputs go with the sample's first call (the one that sends). */
    for (pass = 0; pass < kSequenceCallsPerSample && ok; ++pass) {
    ok = sequence_check_exchange(dl_simulation_box_exchange(clients[kBox], 0, gravity, boxOut, &particles),
                                 clients[kBox], "dl_simulation_box_exchange");
    /* ParticleSource: on_in, then rate_in, each when it changed. */
    if (ok && pass == 0 && k == kGateOff) {
      ok = sequence_check(dl_particle_source_set_enabled(clients[kSource], 0, 0), clients[kSource], "source off");
    }
    if (ok && pass == 0 && k == kRateStep) {
      ok = sequence_check(dl_particle_source_set_rate(clients[kSource], 0, kRateHigh), clients[kSource], "rate");
    }
    ok = ok && sequence_check_exchange(dl_particle_source_read(clients[kSource], 0, sourceCounts, sourceMasses),
                                       clients[kSource], "dl_particle_source_read");
    /* ParticleSink: declared on, on_in false from the start, true from kSinkOn. */
    if (ok && pass == 0 && (k == 0 || k == kSinkOn)) {
      ok = sequence_check(dl_particle_sink_set_enabled(clients[kSink], 0, k == kSinkOn), clients[kSink], "sink");
    }
    ok = ok && sequence_check_exchange(dl_particle_sink_read(clients[kSink], 0, sinkCounts, sinkMasses),
                                       clients[kSink], "dl_particle_sink_read");
    /* RegionSensor: the size input differs from the declaration at once, the centre at kPileMove. */
    if (ok && pass == 0 && (k == 0 || k == kPileMove)) {
      ok = sequence_check(dlm_region_sensor_set_region(clients[kPile], 0, 1, pileCentre, orientation, 1, 0, pileSize,
                                                       0.5),
                          clients[kPile], "sensor region");
    }
    ok = ok && sequence_check_exchange(dl_region_sensor_read(clients[kPile], 0, &pileCount, pileOut), clients[kPile],
                                       "dl_region_sensor_read");
    }
    if (!ok) break;
    /* Outputs at sample k are those of the interval that begins at k: an input sent at
     * sample j shows in the outputs of j on. */
    delivered = sourceMasses[1];
    shortfall = sourceCounts[2];
    removed = sinkMasses[1];
    pileMass = pileOut[0];
    worldMass = boxOut[1];
    if (k == kGateOff - 2) deliveredAtGateMinus = delivered;
    if (k == kGateOff - 1) deliveredBeforeGate = delivered;
    if (k == kGateOff) deliveredAtGate = delivered;
    if (k == kPileMove - 1) pileBeforeMove = pileMass;
    if (k == kSinkOn - 1) {
      pileBeforeSink = pileMass;
      worldBeforeSink = worldMass;
      removedBeforeSink = removed;
    }
  }
  ok = sequence_finish(clients, kCount) && ok;
  printf("switched_source_sequence: %d samples, delivered %g kg (shortfall %d; at the gate %g kg, after it %g kg), "
         "pile %g kg before the move, %g kg before the sink (world %g kg, removed %g kg), at the end pile %d "
         "particles %g kg, removed %g kg, world %d particles %g kg\n",
         k, delivered, shortfall, deliveredBeforeGate, deliveredAtGate, pileBeforeMove, pileBeforeSink,
         worldBeforeSink, removedBeforeSink, pileCount, pileMass, removed, particles, worldMass);
  fflush(stdout);
  if (!ok) return 1;
  /* 4 kg/s for 0.1 s, then 8 kg/s for 0.1 s: 1.2 kg, within two particle masses. */
  if (!(fabs(delivered - (kRateLow + kRateHigh) * 0.1) <= 2.0 * kParticleMassMax && shortfall == 0)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the source delivers 4 kg/s x 0.1 s + 8 kg/s x 0.1 s");
  }
  /* Still pouring in the last interval before the gate; nothing after it. */
  if (!(deliveredBeforeGate > deliveredAtGateMinus && deliveredAtGate == deliveredBeforeGate &&
        delivered == deliveredAtGate)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the delivered mass stops growing when the source is off");
  }
  /* The sensor above the source saw nothing; on the floor it weighs the pile (a few
   * particles may bounce off the floor's volume: 5 %). */
  if (!(pileBeforeMove == 0.0 && pileBeforeSink >= 0.95 * delivered && pileBeforeSink <= delivered * (1 + 1e-12))) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the moved sensor weighs the pile");
  }
  /* The sink removed nothing while off, although the pile lies in it. */
  if (!(removedBeforeSink == 0.0 && fabs(worldBeforeSink - delivered) <= 1e-9 * delivered)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the switched-off sink keeps the pile");
  }
  /* Switched on, it removes the pile: mass is conserved between the world and the sink. */
  if (!(removed >= 0.95 * delivered && fabs(worldMass + removed - worldBeforeSink) <= 1e-9 * delivered &&
        pileMass == 0.0)) {
    ok = sequence_check(DL_ERR_INTERNAL, NULL, "the switched-on sink removes the pile");
  }
  return ok ? 0 : 1;
}
