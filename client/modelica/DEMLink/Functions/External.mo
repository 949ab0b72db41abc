within DEMLink.Functions;
package External "The C functions of libdemlink_c (demlink/demlink_c.h); each returns a dl_status (0: OK)"
  extends Modelica.Icons.InternalPackage;

  impure function lastError "dl_last_error"
    input Client client;
    output String message;
    external "C" message = dl_last_error(client)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end lastError;

  impure function setTimeout "dl_set_timeout"
    input Client client;
    input Real seconds;
    output Integer status;
    external "C" status = dl_set_timeout(client, seconds)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end setTimeout;

  impure function connectToHost "dl_connect_to_host"
    input Client client;
    input String address;
    input Integer port;
    input String clientName;
    input String token;
    output Integer status;
    external "C" status = dl_connect_to_host(client, address, port, clientName, token)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end connectToHost;

  impure function declareSimulationBox "dl_declare_simulation_box_ex"
    input Client client;
    input String name;
    input Real interval;
    input Real timeStep;
    input Real endTime;
    input Real gravity[3];
    input Real boundsLower[3];
    input Real boundsUpper[3];
    input Integer expectedCount;
    input Real restitutionTolerance;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_simulation_box_ex(client, name, interval, timeStep, endTime, gravity,
      boundsLower, boundsUpper, expectedCount, restitutionTolerance, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareSimulationBox;

  impure function declareMaterial "dl_declare_material"
    input Client client;
    input String name;
    input String databaseName;
    input Real density;
    input Real youngsModulus;
    input Real poissonRatio;
    input Real restitution;
    input Real slidingFriction;
    input Real rollingFriction;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_material(client, name, databaseName, density, youngsModulus, poissonRatio,
      restitution, slidingFriction, rollingFriction, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareMaterial;

  impure function declareRigidBodyStl "dl_declare_rigid_body_stl"
    input Client client;
    input String name;
    input Real interval;
    input String stlFile;
    input String material;
    input Real referencePoint[3];
    input Real pose[7];
    input Integer motion;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_rigid_body_stl(client, name, interval, stlFile, material, referencePoint,
      pose, motion, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareRigidBodyStl;

  impure function declareRegionSensorBox "dl_declare_region_sensor_box"
    input Client client;
    input String name;
    input Real interval;
    input Real centre[3];
    input Real size[3];
    input String attachedTo;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_region_sensor_box(client, name, interval, centre, size, attachedTo, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareRegionSensorBox;

  impure function declareParticleSourceBox "dl_declare_particle_source_box"
    input Client client;
    input String name;
    input Real interval;
    input String material;
    input Real centre[3];
    input Real halfExtents[3];
    input Real rMin;
    input Real rMax;
    input Real ratePerSecond;
    input Real rateKgPerSecond;
    input Real velocity[3];
    input Integer seed;
    output Integer status;
    output Integer handle;
    external "C" status = dl_declare_particle_source_box(client, name, interval, material, centre, halfExtents,
      rMin, rMax, ratePerSecond, rateKgPerSecond, velocity, seed, handle)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end declareParticleSourceBox;

  impure function simulationBoxExchange "dl_simulation_box_exchange"
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
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer count;
    output Real out[7];
    external "C" status = dl_region_sensor_read(client, handle, count, out)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end regionSensorRead;

  impure function particleSourceRead "dl_particle_source_read"
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer counts[3];
    output Real masses[3];
    external "C" status = dl_particle_source_read(client, handle, counts, masses)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end particleSourceRead;

  impure function finish "dl_finish: Bye without waiting"
    input Client client;
    input String reason;
    output Integer status;
    external "C" status = dl_finish(client, reason)
      annotation (Library = "demlink_c", Include = "#include \"demlink/demlink_c.h\"");
  end finish;
end External;
