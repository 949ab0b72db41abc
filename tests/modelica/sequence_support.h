/* Shared by the C programs that make a DEMLink Modelica example's exact call sequence:
 * one connected client per component (the ExternalObject constructors), then in each
 * initial algorithm the repeated connect, the declaration and DeclarationsDone
 * (Functions.connectClient, Functions.declare -> dlm_declare, Functions.declarationsDone),
 * Bye for every component at terminal(), then the destructors. */
#ifndef DEMLINK_TESTS_SEQUENCE_SUPPORT_H
#define DEMLINK_TESTS_SEQUENCE_SUPPORT_H

#include <stdio.h>

#include "demlink_modelica.h"

/* 1 when status is DL_OK; else prints what failed with the client's message and returns 0. */
static int sequence_check(int status, dl_client* client, const char* what) {
  if (status == DL_OK) return 1;
  fprintf(stderr, "sequence: %s failed (status %d, server code %d): %s\n", what, status,
          client != NULL ? dl_last_server_error_code(client) : 0, client != NULL ? dl_last_error(client) : "no client");
  return 0;
}

/* A finished run (DL_ERR_FINISHED) is no error for an exchange: Functions.checkExchange. */
static int sequence_check_exchange(int status, dl_client* client, const char* what) {
  return status == DL_ERR_FINISHED || sequence_check(status, client, what);
}

/* Calls of each component's exchange per sample (DL_ORDER_SEND_FIRST_SPLIT, set by
 * dlm_client_connect): the .mo files call it at sample(0, tc), which sends the inputs at t,
 * and again in the event iteration after every component's first call, which returns
 * [t, t + tc]. A replay runs its sample's calls once per pass, in the model's order. */
enum { kSequenceCallsPerSample = 2 };

/* Where the constructors connected (Functions.connectClient repeats it in each initial algorithm). */
static const char* sequence_host = NULL;
static int sequence_port = 0;
static double sequence_timeout = 0.0;

/* The ExternalObject constructors of every component (Client.constructor ->
 * dlm_client_connect): all connections are open before the first initial algorithm. The
 * names are the components' names (each client is named after its component). */
static int sequence_connect(dl_client** clients, const char* const* names, int count, const char* host, int port,
                            double timeout) {
  int i;
  sequence_host = host;
  sequence_port = port;
  sequence_timeout = timeout;
  for (i = 0; i < count; ++i) {
    clients[i] = dlm_client_connect(host, port, names[i], "", timeout);
    if (clients[i] == NULL) return sequence_check(DL_ERR_INTERNAL, NULL, "dlm_client_connect");
  }
  return 1;
}

/* One component's initial algorithm: Functions.connectClient (a no-op on the connected
 * client), Functions.declare (strings {kind, name, ...}, reals {interval, ...}) and
 * Functions.declarationsDone. */
static int sequence_declare(dl_client* client, const int* ints, int nInts, const double* reals, int nReals,
                            const char** strings, int nStrings) {
  return sequence_check(dl_set_timeout(client, sequence_timeout), client, "dl_set_timeout") &&
         sequence_check(dl_connect_to_host(client, sequence_host, sequence_port, strings[1], ""), client,
                        "dl_connect_to_host") &&
         sequence_check(dlm_declare(client, ints, nInts, reals, nReals, strings, nStrings), client, strings[1]) &&
         sequence_check(dl_declarations_done(client), client, "dl_declarations_done");
}

/* The initial algorithms every example starts with: its SimulationBox (tc, gravity
 * -g z, the bounds, nComponents 0 and every optional setting at its default), the
 * Material "gravel" from the database and a horizontal Plane at height planeZ. */
static int sequence_declare_room(dl_client* box, dl_client* gravel, dl_client* plane, const char* planeName,
                                 double tc, double g, const double lower[3], const double upper[3], double planeZ) {
  const double nan = dlm_not_given();
  const int boxInts[5] = {0, -1, 0, 0, 0};
  const double boxReals[16] = {tc,       nan,      0.0,      0.0,      0.0, -g,  lower[0], lower[1],
                               lower[2], upper[0], upper[1], upper[2], nan, nan, nan,      nan};
  const char* boxStrings[2] = {"simulation_box", "simBox"};
  const double gravelReals[7] = {0.0, nan, nan, nan, nan, nan, nan};
  const char* gravelStrings[3] = {"material", "gravel", "gravel"};
  const double planeReals[7] = {0.0, 0.0, 0.0, planeZ, 0.0, 0.0, 1.0};
  const char* planeStrings[3] = {"plane", planeName, "gravel"};
  return sequence_declare(box, boxInts, 5, boxReals, 16, boxStrings, 2) &&
         sequence_declare(gravel, NULL, 0, gravelReals, 7, gravelStrings, 3) &&
         sequence_declare(plane, NULL, 0, planeReals, 7, planeStrings, 3);
}

/* terminal(): Functions.finish of every component; then the destructors (Client.destructor). */
static int sequence_finish(dl_client** clients, int count) {
  int ok = 1;
  int i;
  for (i = 0; i < count; ++i) {
    if (clients[i] != NULL) ok = sequence_check(dl_finish(clients[i], "terminal()"), clients[i], "dl_finish") && ok;
  }
  for (i = 0; i < count; ++i) dlm_client_destroy(clients[i]);
  return ok;
}

#endif /* DEMLINK_TESTS_SEQUENCE_SUPPORT_H */
