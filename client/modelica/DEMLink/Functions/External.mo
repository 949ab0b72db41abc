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

  impure function declarationsDone "dl_declarations_done: this client declares nothing more"
    extends Modelica.Icons.Function;
    input Client client;
    output Integer status;
    external "C" status = dl_declarations_done(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declarationsDone;

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

  impure function regionSensorReadBonds "dl_region_sensor_read_bonds"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer count;
    output Real out[7];
    output Integer bonds[2] "Intact, broken parallel bonds inside";
    external "C" status = dl_region_sensor_read_bonds(client, handle, count, out, bonds)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end regionSensorReadBonds;

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

  impure function particleViewRead "dlm_particle_view_read: dl_particle_view_read_ex with the ids as Integers"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer capacity;
    output Integer status;
    output Real positions[3 * capacity];
    output Real velocities[3 * capacity];
    output Real radii[capacity];
    output Integer ids[capacity];
    output Integer count;
    external "C" status = dlm_particle_view_read(client, handle, capacity, positions, velocities, radii, ids, count)
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end particleViewRead;

  impure function particleSourceSetEnabled "dl_particle_source_set_enabled: on (1) / off (0) from the next package on"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer on;
    output Integer status;
    external "C" status = dl_particle_source_set_enabled(client, handle, on)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSourceSetEnabled;

  impure function particleSourceSetRate "dl_particle_source_set_rate: the rate in the declared unit from the next package on"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Real rate;
    output Integer status;
    external "C" status = dl_particle_source_set_rate(client, handle, rate)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSourceSetRate;

  impure function particleSinkSetEnabled "dl_particle_sink_set_enabled: on (1) / off (0) from the next package on"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer on;
    output Integer status;
    external "C" status = dl_particle_sink_set_enabled(client, handle, on)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSinkSetEnabled;

  impure function regionSensorSetRegion "dlm_region_sensor_set_region: dl_region_sensor_set_region with each part optional"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer sendPose "1: send centre and orientation";
    input Real centre[3];
    input Real orientation[4];
    input Integer sendSize "1: send the size (box) or radius (sphere)";
    input Integer sphere "1: a sphere sensor (radius), 0: a box (size)";
    input Real size[3];
    input Real radius;
    output Integer status;
    external "C" status = dlm_region_sensor_set_region(client, handle, sendPose, centre, orientation, sendSize, sphere,
      size, radius) annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end regionSensorSetRegion;

  impure function simulationBoxSetFrame "dl_simulation_box_set_frame: the frame's motion from the next package on"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Real linearAcceleration[3];
    input Real angularVelocity[3];
    input Real angularAcceleration[3];
    input Real origin[3];
    output Integer status;
    external "C" status = dl_simulation_box_set_frame(client, handle, linearAcceleration, angularVelocity,
      angularAcceleration, origin) annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end simulationBoxSetFrame;

  impure function declareMassSpringBox "dl_declare_mass_spring_box"
    extends Modelica.Icons.Function;
    input Client client;
    input String name;
    input Real interval;
    input String material;
    input Real lo[3];
    input Real hi[3];
    input Real nodeSpacing;
    input Real springs[3];
    input Real breakLimits[2];
    input Integer fixedCount;
    input Real fixedRegions[6 * fixedCount] "lo x y z, hi x y z per box";
    input Integer drivenCount;
    input Real drivenRegions[6 * drivenCount] "lo x y z, hi x y z per box";
    input Real drivenReference[3];
    input String attachedTo;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_mass_spring_box(client, name, interval, material, lo, hi, nodeSpacing, springs,
      breakLimits, fixedCount, fixedRegions, drivenCount, drivenRegions, drivenReference, attachedTo, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareMassSpringBox;

  impure function declareFemMesh "dl_declare_fem_mesh"
    extends Modelica.Icons.Function;
    input Client client;
    input String name;
    input Real interval;
    input String material;
    input String mshFile;
    input Real elastic[3];
    input Real rayleigh[2];
    input Integer fixedCount;
    input Real fixedRegions[6 * fixedCount] "lo x y z, hi x y z per box";
    input Integer drivenCount;
    input Real drivenRegions[6 * drivenCount] "lo x y z, hi x y z per box";
    input Real drivenReference[3];
    input String attachedTo;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_fem_mesh(client, name, interval, material, mshFile, elastic, rayleigh, fixedCount,
      fixedRegions, drivenCount, drivenRegions, drivenReference, attachedTo, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareFemMesh;

  impure function deformableBodyExchange "dlm_deformable_body_exchange: dl_deformable_body_exchange with the pose optional"
    extends Modelica.Icons.Function;
    input Client client;
    input Integer handle;
    input Integer sendPose;
    input Real pose[7];
    input Real twist[6];
    output Integer status;
    output Real reactions[12];
    output Integer broken;
    external "C" status = dlm_deformable_body_exchange(client, handle, sendPose, pose, twist, reactions, broken)
      annotation (Library = "demlink_c", Include = "#include \"demlink_modelica.h\"");
  end deformableBodyExchange;

  impure function finish "dl_finish: Bye without waiting"
    extends Modelica.Icons.Function;
    input Client client;
    input String reason;
    output Integer status;
    external "C" status = dl_finish(client, reason)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end finish;
end External;
