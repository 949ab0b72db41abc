/* Helpers the DEMLink Modelica package calls besides demlink/demlink_c.h (docs/modelica.md).
 *
 * Why: a Modelica Integer is a C int, but the generic package of the C ABI takes long long
 * ints, so a declaration cannot be passed from Modelica to dl_set_data directly; and
 * Modelica has no literal for NaN, the C ABI's "not given". Both are bridged here, in C
 * the tool compiles with the model (Include annotation), so libdemlink_c stays unchanged. */
#ifndef DEMLINK_MODELICA_H
#define DEMLINK_MODELICA_H

#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "demlink/demlink_c.h"

/* Declares one component from the generic declare layout (demlink_c.h, "Generic layout":
 * strings[0] kind, strings[1] name, reals[0] communication interval). Each Modelica
 * component owns its client, so the component's handle is 0. Returns a dl_status. */
static int dlm_declare(dl_client* client, const int* ints, int nInts, const double* reals, int nReals,
                       const char** strings, int nStrings) {
  long long* wide = NULL;
  dl_package* package;
  int status;
  int i;
  if (nInts < 0) return DL_ERR_ARGUMENT;
  package = dl_package_create();
  if (package == NULL) return DL_ERR_INTERNAL;
  if (nInts > 0) {
    wide = (long long*)malloc((size_t)nInts * sizeof *wide);
    if (wide == NULL) {
      dl_package_destroy(package);
      return DL_ERR_INTERNAL;
    }
    for (i = 0; i < nInts; ++i) wide[i] = ints[i];
  }
  status = dl_set_data(package, wide, nInts, reals, nReals, strings, nStrings);
  if (status == DL_OK) status = dl_send_package(client, package);
  free(wide);
  dl_package_destroy(package);
  return status;
}

/* The ExternalObject constructor: a client with the timeout set and the split send-first
 * order (DL_ORDER_SEND_FIRST_SPLIT: each component calls its exchange twice per sample,
 * at the sample and in the event iteration after it, so the outputs at t are those of
 * [t, t + tc] while every component of the model runs in one thread), connected to the server.
 * Tools construct every ExternalObject before the initial algorithms run, so all of a
 * model's connections are open before the first component declares and says its
 * declarations are done (docs/modelica.md). A failed connect leaves the client
 * unconnected; the initial algorithm's dl_connect_to_host (a no-op when connected) tries
 * again and reports the failure with its message. NULL only when out of memory. */
static dl_client* dlm_client_connect(const char* host, int port, const char* clientName, const char* token,
                                     double timeout) {
  dl_client* client = dl_client_create();
  if (client == NULL) return NULL;
  if (dl_set_timeout(client, timeout) == DL_OK && dl_set_exchange_order(client, DL_ORDER_SEND_FIRST_SPLIT) == DL_OK) {
    (void)dl_connect_to_host(client, host, port, clientName, token);
  }
  return client;
}

/* The ExternalObject destructor: Bye (a no-op after terminal()'s, and when not connected),
 * then close. A run the tool ends without terminal() (an error, a stop) thus still ends
 * the DEM run as "said Bye" instead of as a lost connection. */
static void dlm_client_destroy(dl_client* client) {
  if (client == NULL) return;
  (void)dl_finish(client, "destructor");
  dl_client_destroy(client);
}

/* A deformable body's exchange without node displacements; sendPose = 0 sends no pose (the
 * driven nodes keep their last one, or follow the body they are attached to). */
static inline int dlm_deformable_body_exchange(dl_client* client, int component, int sendPose, const double* pose,
                                               const double* twist, double* reactions, int* broken) {
  int count = 0;
  return dl_deformable_body_exchange(client, component, sendPose ? pose : NULL, sendPose ? twist : NULL, reactions, 0,
                                     NULL, &count, broken);
}

/* A region sensor's run-time region: sendPose = 0 keeps centre and orientation, sendSize = 0
 * keeps the extent; otherwise a sphere sensor (sphere = 1) gets the radius, a box the size. */
static inline int dlm_region_sensor_set_region(dl_client* client, int component, int sendPose,
                                               const double* centre, const double* orientation, int sendSize,
                                               int sphere, const double* size, double radius) {
  return dl_region_sensor_set_region(client, component, sendPose ? centre : NULL, sendPose ? orientation : NULL,
                                     sendSize && !sphere ? size : NULL, sendSize && sphere ? radius : NAN);
}

/* The particle view with velocities and the particles' stable ids, the ids as Modelica
 * Integers (C int): an id above INT_MAX is given as -1. positions and velocities hold
 * 3 * capacity reals, radii and ids capacity values. */
static inline int dlm_particle_view_read(dl_client* client, int component, int capacity, double* positions,
                                         double* velocities, double* radii, int* ids, int* count) {
  uint64_t* wide = NULL;
  int status;
  int i;
  if (capacity < 0) return DL_ERR_ARGUMENT;
  if (capacity > 0) {
    wide = (uint64_t*)malloc((size_t)capacity * sizeof *wide);
    if (wide == NULL) return DL_ERR_INTERNAL;
  }
  *count = 0;
  status = dl_particle_view_read_ex(client, component, capacity, positions, velocities, radii, wide, count);
  if (status == DL_OK || status == DL_ERR_CAPACITY) {
    for (i = 0; i < capacity && i < *count; ++i) ids[i] = wide[i] > (uint64_t)INT_MAX ? -1 : (int)wide[i];
  }
  free(wide);
  return status;
}

/* NaN: "not given" in an optional real of the generic layout. */
static double dlm_not_given(void) { return NAN; }

#endif /* DEMLINK_MODELICA_H */
