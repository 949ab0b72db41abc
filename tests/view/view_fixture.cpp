// Serves the live view of several scenes stepping at once, each on a thread of its own and
// offered to one LiveViewHub as demlink-server's simulations are (named by the scene file's
// stem), without co-simulation clients: for the browser test of choosing a simulation.
//
//   demlink_view_fixture SECONDS SCENE...
//
// Prints "view: URL", steps each scene at most one simulated second per wall second until
// its end_time, then closes it (its pages move to the default, as when a server's simulation
// finishes), and exits after SECONDS.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "demlink/server/view/live_view_hub.hpp"
#include "demlink/server/view/view_server.hpp"

namespace {

using namespace demlink::server;
using Clock = std::chrono::steady_clock;

void stepPaced(TranslatedScene& scene, LiveViewHub& hub, const std::string& name, const std::atomic<bool>& stop) {
  demlink::core::World& world = scene.world;
  if (!world.initialized()) world.initialize();
  hub.announce(world, name);
  hub.offer(world);
  const Clock::time_point start = Clock::now();
  const double endTime = scene.run.end_time;
  while (!stop.load() && world.time() < endTime) {
    world.advance(1);
    hub.offer(world);
    const double ahead = world.time() - std::chrono::duration<double>(Clock::now() - start).count();
    if (ahead > 1.0e-3) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
  }
  hub.release(world);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: demlink_view_fixture SECONDS SCENE...\n");
    return 2;
  }
  try {
    const double seconds = std::stod(argv[1]);
    std::vector<std::unique_ptr<TranslatedScene>> scenes;
    std::vector<std::string> names;
    for (int k = 2; k < argc; ++k) {
      const std::filesystem::path path(argv[k]);
      const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
      scenes.emplace_back(new TranslatedScene(translateScene(loadSceneFile(path.string()), folder)));
      names.push_back(path.stem().string());
    }
    LiveViewHub hub;
    ViewServer view(hub, {});
    view.start();
    std::printf("view: %s\n", view.url().c_str());
    std::fflush(stdout);
    std::atomic<bool> stop{false};
    std::vector<std::thread> threads;
    for (std::size_t k = 0; k < scenes.size(); ++k) {
      threads.emplace_back(stepPaced, std::ref(*scenes[k]), std::ref(hub), names[k], std::cref(stop));
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    stop = true;
    for (std::thread& thread : threads) thread.join();
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
}
