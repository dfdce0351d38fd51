// KITTI calib.txt reading: KITTI's own layout (odometry sequence 00's values, as its devkit
// distributes them), TrainSim's additions (Tr_1, D2), and what is refused with the line named.
#include <gtest/gtest.h>

#include <string>

#include "trainsim/core/error.hpp"
#include "trainsim/io/kitti_calib.hpp"

namespace trainsim::io {
namespace {

TEST(KittiCalib, ReadsKittisOwnFileAndTrainSimsExtraLines) {
  const std::string text =
      "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 "
      "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
      "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n"
      "P1: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.861448000000e+02 "
      "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
      "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\r\n"
      "\n"
      "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
      "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
      "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n"
      "Tr_1: 1 0 0 0 0 1 0 0 0 0 1 0\n"
      "D2: -0.1 0.01 0 0 0";
  const KittiCalib calib = parseKittiCalib(text, "calib.txt");
  ASSERT_EQ(calib.size(), 5u);
  ASSERT_EQ(calib.at("P0").size(), 12u);
  EXPECT_EQ(calib.at("P0")[0], 718.856);
  EXPECT_EQ(calib.at("P1")[3], -386.1448);
  EXPECT_EQ(calib.at("P1")[11], 0.0);
  EXPECT_EQ(calib.at("Tr")[11], -2.921968648686e-01);
  EXPECT_EQ(calib.at("Tr_1").size(), 12u);
  EXPECT_EQ(calib.at("D2"), (std::vector<double>{-0.1, 0.01, 0.0, 0.0, 0.0}));
}

TEST(KittiCalib, RefusesWhatIsNotNameAndNumbersNamingTheLine) {
  const auto problem = [](const std::string& text) {
    try {
      parseKittiCalib(text, "seq/calib.txt");
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(problem("P0: 1 2\nno colon here\n"), "seq/calib.txt:2: not 'NAME: numbers'");
  EXPECT_EQ(problem(": 1 2\n"), "seq/calib.txt:1: not 'NAME: numbers'");
  EXPECT_EQ(problem("\nTr: 1 2x 3\n"), "seq/calib.txt:2: Tr: '2x' is not a finite number");
  EXPECT_EQ(problem("Tr: 1 nan\n"), "seq/calib.txt:1: Tr: 'nan' is not a finite number");
  EXPECT_EQ(problem("Tr: 1e999\n"), "seq/calib.txt:1: Tr: '1e999' is not a finite number");
  EXPECT_EQ(problem("P2: 1\nP2: 2\n"), "seq/calib.txt:2: P2 is given twice");
  EXPECT_EQ(problem("P2:\n"), "accepted");  // a name without numbers: the reader decides
}

}  // namespace
}  // namespace trainsim::io
