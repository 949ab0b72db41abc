within DEMLink.Functions;
class Client "One connection to demlink-server (an ExternalObject around dl_client)"
  extends ExternalObject;

  function constructor "dlm_client_connect: a client connected to the server (a failed connect is reported by the initial algorithm)"
    extends Modelica.Icons.Function;
    input String address "Host of demlink-server";
    input Integer port "Its TCP port";
    input String clientName "The component's name";
    input String token "Access token (empty: none)";
    input Real timeout "Longest wait for the server in one call [s]";
    output Client client;
    external "C" client = dlm_client_connect(address, port, clientName, token, timeout)
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end constructor;

  function destructor "dlm_client_destroy: Bye (if terminal() did not say it) and close the connection"
    extends Modelica.Icons.Function;
    input Client client;
    external "C" dlm_client_destroy(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end destructor;
  annotation (Documentation(info = "<html><p>Each DEMLink component owns one Client: one TCP
connection to the server with this one component on it (its client-local handle is 0).</p>
<p>The constructor connects. Tools construct every ExternalObject of a model before they
run its initial algorithms, so every component's connection is open before any component
declares; the server then knows every client of the model and compiles once each has
said that its declarations are done (at the end of its initial algorithm): nobody counts
the components.</p></html>"));
end Client;
