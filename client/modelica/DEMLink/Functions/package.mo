within DEMLink;
package Functions "Calls into libdemlink_c; the declare functions stop the simulation with the server's message on failure"
  extends Modelica.Icons.FunctionsPackage;

  impure function check "Stops the simulation with the client's last error when status is not 0 (DL_OK)"
    input Client client;
    input Integer status;
  algorithm
    assert(status == 0, "DEMLink: " + External.lastError(client) + " (status " + String(status) + ")");
  end check;

  impure function setTimeout
    input Client client;
    input Real seconds;
    output Integer status;
  algorithm
    status := External.setTimeout(client, seconds);
  end setTimeout;

  impure function connectToHost
    input Client client;
    input String address;
    input Integer port;
    input String clientName;
    input String token;
    output Integer status;
  algorithm
    status := External.connectToHost(client, address, port, clientName, token);
  end connectToHost;

  impure function declareSimulationBox
    input Client client;
    input String name;
    input Real interval;
    input Real timeStep;
    input Real endTime;
    input Real gravity[3];
    input Real boundsLower[3];
    input Real boundsUpper[3];
    input Integer expectedCount;
    input Real restitutionTolerance = 0.01 "Largest restitution error the time-step limit allows";
    output Integer handle;
  protected
    Integer status;
  algorithm
    (status, handle) := External.declareSimulationBox(client, name, interval, timeStep, endTime, gravity,
      boundsLower, boundsUpper, expectedCount, restitutionTolerance);
    check(client, status);
  end declareSimulationBox;

  impure function declareMaterial
    input Client client;
    input String name;
    input String databaseName;
    input Real density;
    input Real youngsModulus;
    input Real poissonRatio;
    input Real restitution;
    input Real slidingFriction;
    input Real rollingFriction;
    output Integer handle;
  protected
    Integer status;
  algorithm
    (status, handle) := External.declareMaterial(client, name, databaseName, density, youngsModulus,
      poissonRatio, restitution, slidingFriction, rollingFriction);
    check(client, status);
  end declareMaterial;

  impure function declareRigidBodyStl
    input Client client;
    input String name;
    input Real interval;
    input String stlFile;
    input String material;
    input Real referencePoint[3];
    input Real pose[7];
    input Integer motion;
    output Integer handle;
  protected
    Integer status;
  algorithm
    (status, handle) := External.declareRigidBodyStl(client, name, interval, stlFile, material, referencePoint,
      pose, motion);
    check(client, status);
  end declareRigidBodyStl;

  impure function declareRegionSensorBox
    input Client client;
    input String name;
    input Real interval;
    input Real centre[3];
    input Real size[3];
    input String attachedTo;
    output Integer handle;
  protected
    Integer status;
  algorithm
    (status, handle) := External.declareRegionSensorBox(client, name, interval, centre, size, attachedTo);
    check(client, status);
  end declareRegionSensorBox;

  impure function declareParticleSourceBox
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
    output Integer handle;
  protected
    Integer status;
  algorithm
    (status, handle) := External.declareParticleSourceBox(client, name, interval, material, centre, halfExtents,
      rMin, rMax, ratePerSecond, rateKgPerSecond, velocity, seed);
    check(client, status);
  end declareParticleSourceBox;

  impure function simulationBoxExchange
    input Client client;
    input Integer handle;
    input Real gravity[3];
    output Integer status;
    output Real out[4];
    output Integer particleCount;
  algorithm
    (status, out, particleCount) := External.simulationBoxExchange(client, handle, gravity);
  end simulationBoxExchange;

  impure function rigidBodyExchange
    input Client client;
    input Integer handle;
    input Real pose[7];
    input Real twist[6];
    output Integer status;
    output Real wrench[12];
  algorithm
    (status, wrench) := External.rigidBodyExchange(client, handle, pose, twist);
  end rigidBodyExchange;

  impure function regionSensorRead
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer count;
    output Real out[7];
  algorithm
    (status, count, out) := External.regionSensorRead(client, handle);
  end regionSensorRead;

  impure function particleSourceRead
    input Client client;
    input Integer handle;
    output Integer status;
    output Integer counts[3];
    output Real masses[3];
  algorithm
    (status, counts, masses) := External.particleSourceRead(client, handle);
  end particleSourceRead;

  impure function finish
    input Client client;
    input String reason;
    output Integer status;
  algorithm
    status := External.finish(client, reason);
  end finish;
end Functions;
