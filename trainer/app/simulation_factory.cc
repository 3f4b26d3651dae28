// For now colosim simulates the colon alone (trainer/colon_simulation.h): the scope
// inputs are recorded and replayed but move nothing. The colon + scope simulation
// replaces the factory below; the renderer replaces makeFrameWriter.
#include "trainer/app/simulation_factory.h"

#include "trainer/colon_simulation.h"

namespace colosim::app {

SimulationFactory simulationFactory() { return makeColonOnlySimulation; }

FrameWriter makeFrameWriter(const std::string& /*dir*/, const std::string& /*view*/, int /*width_px*/,
                            int /*height_px*/) {
  return {};
}

}  // namespace colosim::app
