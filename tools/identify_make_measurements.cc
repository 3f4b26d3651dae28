// Writes the shipped example tension tests: identify_make_measurements assets/measurements
// (tests/identify/shipped_data_test.cc checks that the files are what this writes).
#include <cstdio>
#include <string>

#include "identify/tension/synthetic.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  for (int sample = 1; sample <= 2; ++sample) {
    colosim::TensionTest t = colosim::generateTensionTest(colosim::shippedSampleSpec(sample));
    t.metadata.insert(t.metadata.begin(), {"note", "SYNTHETIC data shaped like Kuehl & Dumont's Figure 8 (sample " +
                                                       std::to_string(sample) +
                                                       " of 2, pig colon, 180 mm, stretched to 0.12 m), not a measurement"});
    const std::string path = std::string(argv[1]) + "/tension_fig8_sample" + std::to_string(sample) + ".csv";
    colosim::writeTensionTest(path, t);
    std::printf("wrote %s (%zu rows)\n", path.c_str(), t.rows());
  }
  return 0;
}
