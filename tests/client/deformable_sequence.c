/* Deformable bodies through the C ABI, against a real server: a mass-spring sheet hung by
 * its four driven corners (dl_declare_mass_spring_box; the pose is held where the sheet was
 * built through dl_deformable_body_exchange) and an FEM beam clamped at one end
 * (dl_declare_fem_mesh, the mesh a file under the server's data root), both under gravity.
 * One client per component in one thread, in the explicit receive-first order
 * (DL_ORDER_RECEIVE_FIRST: one call per sample, never waiting for a later component).
 * Usage: deformable_sequence HOST PORT MSH_FILE SECONDS
 * Prints one line: "sheet <driven Fz> nodes <count> broken <n> beam <fixed Fz> <fixed Fx>"
 * [N], each force the mean over the exchanges of the second half of the run (the sheet,
 * built without shear springs or node drag, still swings: the mean of the reaction over a
 * window T differs from the weight by the change of momentum over T, divided by T).
 * Exits 0 on success, 1 with the error message on any failure. */
#include <stdio.h>
#include <stdlib.h>

#include "demlink/demlink_c.h"

enum { kBox, kMaterial, kSheet, kBeam, kCount };
static const char* const kNames[kCount] = {"box", "steel", "sheet", "beam"};

static int check(int status, dl_client* client, const char* what) {
  if (status != DL_OK) {
    fprintf(stderr, "deformable_sequence: %s failed (status %d, server code %d): %s\n", what, status,
            client != NULL ? dl_last_server_error_code(client) : 0,
            client != NULL ? dl_last_error(client) : "no client");
    return 0;
  }
  return 1;
}

int main(int argc, char** argv) {
  const double tc = 0.01; /* communication interval [s] */
  dl_client* clients[kCount] = {NULL, NULL, NULL, NULL};
  int handles[kCount] = {-1, -1, -1, -1};
  int ok = 1;
  int samples;
  int i;
  int k;
  double sheetReactions[12] = {0};
  double beamReactions[12] = {0};
  double displacements[3 * 64];
  int count = 0;
  int broken = 0;
  double sheetMean = 0.0;
  double beamMean = 0.0;
  double beamMeanX = 0.0;
  int averaged = 0;
  if (argc < 5) {
    fprintf(stderr, "usage: %s HOST PORT MSH_FILE SECONDS\n", argv[0]);
    return 2;
  }
  samples = (int)(atof(argv[4]) / tc + 0.5);
  for (i = 0; i < kCount; ++i) {
    clients[i] = dl_client_create();
    if (clients[i] == NULL) {
      fprintf(stderr, "deformable_sequence: out of memory\n");
      return 1;
    }
    ok = ok && check(dl_set_exchange_order(clients[i], DL_ORDER_RECEIVE_FIRST), clients[i], "dl_set_exchange_order");
    ok = ok && check(dl_connect_to_host(clients[i], argv[1], atoi(argv[2]), kNames[i], ""), clients[i],
                     "dl_connect_to_host");
  }
  {
    const double gravity[3] = {0.0, 0.0, -9.81};
    const double lower[3] = {-1.0, -1.0, -1.0};
    const double upper[3] = {2.0, 2.0, 1.0};
    /* Sheet: 5 x 5 nodes over 0.4 x 0.4 m, 10 kg, corners driven about the centre. */
    const double lo[3] = {0.0, 0.0, -0.01};
    const double hi[3] = {0.4, 0.4, 0.01};
    const double springs[3] = {10.0, 1e4, 300.0};
    const double centre[3] = {0.2, 0.2, 0.0};
    double corners[4 * 6];
    /* Beam: E = 1e8 Pa, nu = 0.3, rho = 1000 kg/m^3; Rayleigh beta damps it to rest. */
    const double elastic[3] = {1e8, 0.3, 1000.0};
    const double rayleigh[2] = {1e-5, 200.0};
    const double clamp[6] = {-1e-6, -1.0, -1.0, 1e-6, 1.0, 1.0};
    for (i = 0; i < 4; ++i) {
      const double x = (i % 2) * 0.4;
      const double y = (i / 2) * 0.4;
      const double box[6] = {x - 0.01, y - 0.01, -0.01, x + 0.01, y + 0.01, 0.01};
      for (k = 0; k < 6; ++k) corners[6 * i + k] = box[k];
    }
    ok = ok && check(dl_declare_simulation_box(clients[kBox], kNames[kBox], tc, 1e-4, samples * tc, gravity, lower,
                                               upper, kCount, &handles[kBox]),
                     clients[kBox], "dl_declare_simulation_box");
    ok = ok && check(dl_declare_material(clients[kMaterial], kNames[kMaterial], "", 7800.0, 2e8, -1, -1, -1, -1,
                                         &handles[kMaterial]),
                     clients[kMaterial], "dl_declare_material");
    ok = ok && check(dl_declare_mass_spring_box(clients[kSheet], kNames[kSheet], tc, kNames[kMaterial], lo, hi, 0.1,
                                                springs, NULL, 0, NULL, 4, corners, centre, "", &handles[kSheet]),
                     clients[kSheet], "dl_declare_mass_spring_box");
    ok = ok && check(dl_declare_fem_mesh(clients[kBeam], kNames[kBeam], tc, kNames[kMaterial], argv[3], elastic,
                                         rayleigh, 1, clamp, 0, NULL, NULL, "", &handles[kBeam]),
                     clients[kBeam], "dl_declare_fem_mesh");
  }
  for (k = 0; k < samples && ok; ++k) {
    double boxOut[4];
    int particles = 0;
    const double pose[7] = {0.2, 0.2, 0.0, 1.0, 0.0, 0.0, 0.0};
    int beamCount = 0;
    int beamBroken = 0;
    ok = check(dl_simulation_box_exchange(clients[kBox], handles[kBox], NULL, boxOut, &particles), clients[kBox],
               "dl_simulation_box_exchange");
    ok = ok && check(dl_deformable_body_exchange(clients[kSheet], handles[kSheet], pose, NULL, sheetReactions, 64,
                                                 displacements, &count, &broken),
                     clients[kSheet], "dl_deformable_body_exchange (sheet)");
    ok = ok && check(dl_deformable_body_exchange(clients[kBeam], handles[kBeam], NULL, NULL, beamReactions, 0, NULL,
                                                 &beamCount, &beamBroken),
                     clients[kBeam], "dl_deformable_body_exchange (beam)");
    if (ok && 2 * k >= samples) {
      sheetMean += sheetReactions[2];
      beamMean += beamReactions[8];
      beamMeanX += beamReactions[6];
      ++averaged;
    }
  }
  if (ok) {
    printf("sheet %.9g nodes %d broken %d beam %.9g %.9g\n", sheetMean / averaged, count, broken,
           beamMean / averaged, beamMeanX / averaged);
    fflush(stdout);
  }
  for (i = 0; i < kCount; ++i) {
    if (dl_finish(clients[i], "done") != DL_OK && ok) {
      fprintf(stderr, "deformable_sequence: dl_finish failed: %s\n", dl_last_error(clients[i]));
      ok = 0;
    }
  }
  for (i = 0; i < kCount; ++i) dl_client_destroy(clients[i]);
  return ok ? 0 : 1;
}
