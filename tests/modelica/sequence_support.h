/* Shared by the C programs that make a DEMLink Modelica example's exact call sequence:
 * one client per component (the ExternalObject constructors), connect and declare in the
 * initial algorithm (Functions.connectClient, Functions.declare -> dlm_declare), Bye for
 * every component at terminal(), then the destructors. */
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

/* Constructors and Functions.connectClient of every component; the names are the
 * components' names (each client is named after its component). */
static int sequence_connect(dl_client** clients, const char* const* names, int count, const char* host, int port,
                            double timeout) {
  int i;
  for (i = 0; i < count; ++i) {
    clients[i] = dl_client_create();
    if (clients[i] == NULL) return sequence_check(DL_ERR_INTERNAL, NULL, "dl_client_create");
  }
  for (i = 0; i < count; ++i) {
    if (!sequence_check(dl_set_timeout(clients[i], timeout), clients[i], "dl_set_timeout")) return 0;
    if (!sequence_check(dl_connect_to_host(clients[i], host, port, names[i], ""), clients[i], "dl_connect_to_host")) {
      return 0;
    }
  }
  return 1;
}

/* Functions.declare: strings {kind, name, ...}, reals {interval, ...}. */
static int sequence_declare(dl_client* client, const int* ints, int nInts, const double* reals, int nReals,
                            const char** strings, int nStrings) {
  return sequence_check(dlm_declare(client, ints, nInts, reals, nReals, strings, nStrings), client, strings[1]);
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
