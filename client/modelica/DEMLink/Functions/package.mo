within DEMLink;
package Functions "Calls into libdemlink_c; failures stop the simulation with the server's message"
  extends Modelica.Icons.FunctionsPackage;

  impure function check "Stops the simulation with the client's last error when status is not 0 (DL_OK)"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer status;
  algorithm
    assert(status == 0, "DEMLink: " + External.lastError(client) + " (status " + String(status) + ")");
  end check;

  impure function checkExchange "Like check, but a finished DEM run (DL_ERR_FINISHED, 6) is no error: the outputs keep their last values"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer status;
  algorithm
    assert(status == 0 or status == 6, "DEMLink: " + External.lastError(client) + " (status " + String(status) + ")");
  end checkExchange;

  impure function connectClient "dl_set_timeout and dl_connect_to_host (a no-op when the constructor connected)"
    extends Modelica.Icons.Function;
    input Client client;
    input String address;
    input Integer port;
    input String clientName;
    input String token;
    input Real timeout "[s]";
  algorithm
    check(client, External.setTimeout(client, timeout));
    check(client, External.connectToHost(client, address, port, clientName, token));
  end connectClient;

  impure function declare "Declares a component: strings {kind, name, ...}, reals {interval, ...} (generic layout, docs/c_abi.md)"
    extends Modelica.Icons.Function;
    input Client client;
    input String kind;
    input String name;
    input Real interval "Communication interval [s] (0: never exchanged)";
    input Integer ints[:];
    input Real reals[:] "The layout's reals from index 1";
    input String strings[:] "The layout's strings from index 2";
  algorithm
    check(client, External.declare(client, ints, cat(1, {interval}, reals), cat(1, {kind, name}, strings)));
  end declare;

  impure function declarationsDone "The end of a component's initialisation: its declarations are done (the server compiles once every client said so)"
    extends Modelica.Icons.Function;
    input Client client;
  algorithm
    check(client, External.declarationsDone(client));
  end declarationsDone;

  function optional "A non-negative value, or NaN (\"not given\": the server's default) for a negative one"
    extends Modelica.Icons.Function;
    input Real value;
    output Real result;
  algorithm
    result := if value >= 0 then value else External.notGiven();
  end optional;

  function changed "True when any element of a differs from the same element of b (Real <> is allowed in functions only)"
    extends Modelica.Icons.Function;
    input Real a[:];
    input Real b[size(a, 1)];
    output Boolean result;
  algorithm
    result := false;
    for i in 1:size(a, 1) loop
      result := result or a[i] <> b[i];
    end for;
  end changed;

  impure function finish "Bye (terminal()); a run that already finished is no error"
    extends Modelica.Icons.Function;
    input Client client;
  algorithm
    check(client, External.finish(client, "terminal()"));
  end finish;
end Functions;
