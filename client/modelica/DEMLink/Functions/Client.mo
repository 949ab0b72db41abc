within DEMLink.Functions;
class Client "One connection to demlink-server (an ExternalObject around dl_client)"
  extends ExternalObject;

  function constructor "dl_client_create"
    extends Modelica.Icons.Function;
    output Client client;
    external "C" client = dl_client_create()
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end constructor;

  function destructor "dlm_client_destroy: Bye (if terminal() did not say it) and close the connection"
    extends Modelica.Icons.Function;
    input Client client;
    external "C" dlm_client_destroy(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end destructor;
  annotation (Documentation(info = "<html><p>Each DEMLink component owns one Client: one TCP
connection to the server with this one component on it (its client-local handle is 0).</p></html>"));
end Client;
