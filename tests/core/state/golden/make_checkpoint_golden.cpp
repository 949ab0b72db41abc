// Writes the golden checkpoint of golden_scene.hpp (see README.md in this folder).
#include <fstream>
#include <iostream>

#include "../golden_scene.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_checkpoint_golden <output file>\n";
    return 2;
  }
  const auto world = demlink::core::test::buildGoldenScene();
  for (int n = 0; n < demlink::core::test::kGoldenSteps; ++n) world->step();
  std::ofstream out(argv[1], std::ios::binary | std::ios::trunc);
  world->saveCheckpoint(out);
  std::cout << "step " << world->stepCount() << ", " << world->particles().size() << " spheres, "
            << world->clumps().size() << " clumps\n";
  return out ? 0 : 1;
}
