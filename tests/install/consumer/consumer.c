/* Links the installed C ABI and uses it without a server: the version, a client, and the
 * status of a connection to a port nobody listens on. Exit 0 when all is as documented. */
#include <stdio.h>
#include <string.h>

#include "demlink/demlink_c.h"

int main(int argc, char** argv) {
  const char* expected = argc > 1 ? argv[1] : "";
  dl_client* client = dl_client_create();
  if (client == NULL) return 1;
  /* Port 1 on loopback: refused at once. */
  const int status = dl_connect_to_host(client, "127.0.0.1", 1, "consumer", NULL);
  printf("demlink_c %s, connect to port 1: status %d (%s)\n", dl_version(), status, dl_last_error(client));
  dl_client_destroy(client);
  if (strcmp(dl_version(), expected) != 0) return 2;
  return status == DL_ERR_CONNECT ? 0 : 3;
}
