within DEMLink.Functions;
package External "The C functions of libdemlink_c (demlink/demlink_c.h) and of Resources/Include/demlink_modelica.h; each int function returns a dl_status (0: OK)"
  extends Modelica.Icons.InternalPackage;

  impure function lastError "dl_last_error"
    extends Modelica.Icons.Function;
    input Client client;
    output String message;
    external "C" message = dl_last_error(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end lastError;

  impure function setTimeout "dl_set_timeout"
    extends Modelica.Icons.Function;
    input Client client;
    input Real seconds;
    output Integer status;
    external "C" status = dl_set_timeout(client, seconds)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end setTimeout;

  impure function connectToHost "dl_connect_to_host"
    extends Modelica.Icons.Function;
    input Client client;
    input String address;
    input Integer port;
    input String clientName;
    input String token;
    output Integer status;
    external "C" status = dl_connect_to_host(client, address, port, clientName, token)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end connectToHost;

  impure function declare "dlm_declare: declares a component from the generic layout (demlink_c.h)"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer ints[:];
    input Real reals[:];
    input String strings[:];
    output Integer status;
    external "C" status = dlm_declare(client, ints, size(ints, 1), reals, size(reals, 1), strings, size(strings, 1))
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end declare;

  pure function notGiven "dlm_not_given: NaN, the generic layout's \"not given\""
    extends Modelica.Icons.Function;
    output Real value;
    external "C" value = dlm_not_given()
      annotation (Include = "#include \"demlink_modelica.h\"");
  end notGiven;

  impure function simulationBoxExchange "dl_simulation_box_exchange"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Real gravity[3];
    output Integer status;
    output Real out[4];
    output Integer particleCount;
    external "C" status = dl_simulation_box_exchange(client, handle, gravity, out, particleCount)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end simulationBoxExchange;

  impure function rigidBodyExchange "dl_rigid_body_exchange"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Real pose[7];
    input Real twist[6];
    output Integer status;
    output Real wrench[12];
    external "C" status = dl_rigid_body_exchange(client, handle, pose, twist, wrench)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end rigidBodyExchange;

  impure function regionSensorRead "dl_region_sensor_read"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer count;
    output Real out[7];
    external "C" status = dl_region_sensor_read(client, handle, count, out)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end regionSensorRead;

  impure function flowSensorRead "dl_flow_sensor_read"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer counts[4];
    output Real masses[4];
    external "C" status = dl_flow_sensor_read(client, handle, counts, masses)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end flowSensorRead;

  impure function particleSourceRead "dl_particle_source_read"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer counts[3];
    output Real masses[3];
    external "C" status = dl_particle_source_read(client, handle, counts, masses)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSourceRead;

  impure function particleSinkRead "dl_particle_sink_read"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer counts[2];
    output Real masses[2];
    external "C" status = dl_particle_sink_read(client, handle, counts, masses)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSinkRead;

  impure function particleViewRead "dl_particle_view_read"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer capacity;
    output Integer status;
    output Real positions[3 * capacity];
    output Real radii[capacity];
    output Integer count;
    external "C" status = dl_particle_view_read(client, handle, capacity, positions, radii, count)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleViewRead;

  impure function finish "dl_finish: Bye without waiting"
    extends Modelica.Icons.Function;
    input Client client;
    input String reason;
    output Integer status;
    external "C" status = dl_finish(client, reason)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end finish;
end External;
