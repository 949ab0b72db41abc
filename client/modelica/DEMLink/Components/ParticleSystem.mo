within DEMLink.Components;
model ParticleSystem "Particles loaded from a saved configuration on the server"
  extends DEMLink.Interfaces.PartialComponent(name = "particles", final kind = "particle_system", final exchanged = false,
    final declInts = {if checkpoint then 1 else 0}, final declReals = fill(0.0, 0), final declStrings = {fileName});
  parameter String fileName = "particles.csv" "File on the SERVER (within its --data-root)";
  parameter Boolean checkpoint = false "true: a checkpoint file; false: a particle CSV (docs/state.md)";
end ParticleSystem;
