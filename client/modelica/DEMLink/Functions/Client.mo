within DEMLink.Functions;
class Client "One connection to demlink-server (an ExternalObject around dl_client)"
  extends ExternalObject;

  function constructor "dl_client_create"
    output Client client;
    external "C" client = dl_client_create()
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end constructor;

  function destructor "dl_client_destroy: closes the connection"
    input Client client;
    external "C" dl_client_destroy(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end destructor;
end Client;
