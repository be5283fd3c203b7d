#include "scene/particle_file.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"
#include "scene/insertion.h"

namespace bouncecal::dem::scene {
namespace {

using bouncecal::testing::ScratchFolder;

namespace fs = std::filesystem;

// Start-positions files written into a folder of their own, removed afterwards.
class ParticleFile : public ::testing::Test {
 protected:
  fs::path Write(const std::string& name, const std::string& text) const {
    const fs::path path = folder_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // The InputError message reading `path` gives, or "" when it reads.
  static std::string ErrorOf(const fs::path& path, int dimension) {
    try {
      ReadParticleFile(path, dimension);
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  }

  // A scene in a cylinder R = 5 cm, H = 20 cm (open top) with one species, reading `path`.
  static Scene CylinderScene(const fs::path& path, std::int64_t count) {
    Scene scene;
    scene.source = "scene.json";
    scene.dimension = 3;
    scene.particles.count = count;
    scene.particles.species = {Species{"steel", 7800, 1}};
    scene.container.kind = ContainerKind::kCylinder;
    scene.container.center_m = {0, 0, 0};
    scene.container.radius_m = 0.05;
    scene.container.height_m = 0.2;
    scene.insertion.kind = InsertionKind::kFile;
    scene.insertion.file = path;
    return scene;
  }

  static std::string ErrorOf(const Scene& scene) {
    try {
      ReadParticleFile(scene);
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  }

  const ScratchFolder folder_;
};

bool Mentions(const std::string& message, const std::string& text) {
  return message.find(text) != std::string::npos;
}

TEST_F(ParticleFile, ByteOrderMarkBeforeTheCsvHeaderIsSkipped) {
  const auto path = Write("bom.csv", "\xEF\xBB\xBFx_m,y_m,z_m,diameter_m\n0,0,0.005,0.01\n");
  const auto particles = ReadParticleFile(path, 3);
  ASSERT_EQ(particles.size(), 1u);
  EXPECT_DOUBLE_EQ(particles[0].radius_m, 0.005);
}

TEST_F(ParticleFile, FilesWithoutParticlesAreRefused) {
  auto message = ErrorOf(Write("empty.csv", ""), 3);
  EXPECT_TRUE(Mentions(message, "empty.csv: is empty")) << message;
  message = ErrorOf(Write("header.csv", "x_m,y_m,z_m,diameter_m\n"), 3);
  EXPECT_TRUE(Mentions(message, "header.csv: holds no particles")) << message;
  message = ErrorOf(Write("zero.data", "LAMMPS data\n\n0 atoms\n\nAtoms # sphere\n\n"), 3);
  EXPECT_TRUE(Mentions(message, "zero.data: holds no particles")) << message;
}

TEST_F(ParticleFile, LammpsAtomCountMustMatchTheAtomsSectionBothWays) {
  const std::string head = "LAMMPS data\n\n2 atoms\n1 atom types\n\nAtoms # sphere\n\n";
  const std::string one = "1 1 0.01 7800 0 0 0.005\n";
  const std::string two = "2 1 0.01 7800 0.02 0 0.005\n";
  auto message = ErrorOf(Write("few.data", head + one), 3);
  EXPECT_TRUE(Mentions(message, "few.data:3: the Atoms section holds 1 of the 2 atoms")) << message;
  // A later section must not be read as atoms, nor hide the missing ones.
  message = ErrorOf(Write("few_vel.data", head + one + "\nVelocities\n\n1 0 0 0 0 0 0\n"), 3);
  EXPECT_TRUE(Mentions(message, "holds 1 of the 2 atoms")) << message;
  message = ErrorOf(Write("many.data", head + one + two + "3 1 0.01 7800 0.04 0 0.005\n"), 3);
  EXPECT_TRUE(Mentions(message, "many.data:10: the Atoms section holds more than the 2 atoms"))
      << message;
  EXPECT_TRUE(Mentions(message, "on line 3")) << message;
  // A garbled row is not taken for the next section's header.
  message = ErrorOf(Write("garbled.data", head + one + "x2 1 0.01 7800 0.02 0 0.005\n"), 3);
  EXPECT_TRUE(Mentions(message, "garbled.data:9: 'x2' is not a finite number")) << message;
  const auto path = Write("good.data", head + one + two + "\nVelocities\n\n1 0 0 0 0 0 0\n");
  EXPECT_EQ(ReadParticleFile(path, 3).size(), 2u);
}

TEST_F(ParticleFile, RepeatedAtomIdsAreRefusedNamingBothLines) {
  const auto message = ErrorOf(Write("dup.data",
                                     "LAMMPS data\n\n2 atoms\n\nAtoms # sphere\n\n"
                                     "7 1 0.01 7800 0 0 0.005\n"
                                     "7 1 0.01 7800 0.02 0 0.005\n"),
                               3);
  EXPECT_TRUE(Mentions(message, "dup.data:8: atom id 7 appears again (first on line 7)"))
      << message;
}

TEST_F(ParticleFile, NonZeroZInA2dSceneIsRefused) {
  auto message = ErrorOf(Write("z.csv", "x_m,y_m,z_m,diameter_m\n0,0,0,0.01\n0.1,0,0.5,0.01\n"), 2);
  EXPECT_TRUE(Mentions(message, "z.csv:3: z = 0.5 m in a 2D scene")) << message;
  message = ErrorOf(
      Write("z.data", "LAMMPS data\n\n1 atoms\n\nAtoms # sphere\n\n1 1 0.01 7800 0 0 5\n"), 2);
  EXPECT_TRUE(Mentions(message, "z.data:7: z = 5 m in a 2D scene")) << message;
  // A z column of zeros is what a 2D writer gives: accepted.
  EXPECT_EQ(ReadParticleFile(Write("flat.csv", "x_m,y_m,z_m,diameter_m\n0,0,0,0.01\n"), 2).size(),
            1u);
}

TEST_F(ParticleFile, CoincidentOrHeavilyOverlappingParticlesAreRefusedNamingBothLines) {
  const std::string header = "x_m,y_m,z_m,diameter_m\n";
  auto message =
      ErrorOf(Write("same.csv", header + "0,0,0.005,0.01\n0.1,0,0.005,0.01\n0,0,0.005,0.01\n"), 3);
  EXPECT_TRUE(Mentions(message,
                       "same.csv:4: particle at (0, 0, 0.005) lies 0 m from the "
                       "particle on line 2"))
      << message;
  // 0.5 (r_i + r_j) = 5 mm: 4.9 mm apart is refused, 5.1 mm apart (a settled contact) is not.
  message = ErrorOf(Write("close.csv", header + "0,0,0.005,0.01\n0.0049,0,0.005,0.01\n"), 3);
  EXPECT_TRUE(Mentions(message, "close.csv:3:")) << message;
  EXPECT_TRUE(Mentions(message, "line 2")) << message;
  EXPECT_EQ(
      ReadParticleFile(Write("touch.csv", header + "0,0,0.005,0.01\n0.0051,0,0.005,0.01\n"), 3)
          .size(),
      2u);
}

// The cell grid against all pairs (HOOMD's habit of testing one thing two ways): random
// polydisperse files, dense enough that some hold a heavy overlap and some do not.
TEST_F(ParticleFile, OverlapGridAgreesWithAllPairs) {
  SceneRandom random(7);
  int refused = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int dimension = trial % 2 == 0 ? 3 : 2;
    const int n = 20 + static_cast<int>(random.Next() % 40);
    std::vector<NewParticle> particles(static_cast<std::size_t>(n));
    std::string text = dimension == 3 ? "x_m,y_m,z_m,diameter_m\n" : "x_m,y_m,diameter_m\n";
    for (auto& p : particles) {
      for (int d = 0; d < dimension; ++d) p.position_m[d] = random.Uniform(-0.05, 0.05);
      p.radius_m = random.Uniform(0.001, 0.008);
      text += fmt::format("{:.17g},{:.17g},", p.position_m[0], p.position_m[1]);
      if (dimension == 3) text += fmt::format("{:.17g},", p.position_m[2]);
      text += fmt::format("{:.17g}\n", 2 * p.radius_m);
    }
    bool heavy = false;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        double dist2 = 0;
        for (int d = 0; d < 3; ++d) {
          const double dx = particles[i].position_m[d] - particles[j].position_m[d];
          dist2 += dx * dx;
        }
        const double limit = 0.5 * (particles[i].radius_m + particles[j].radius_m);
        heavy = heavy || dist2 < limit * limit;
      }
    }
    const auto message = ErrorOf(Write("random.csv", text), dimension);
    EXPECT_EQ(!message.empty(), heavy) << "trial " << trial << ": " << message;
    refused += heavy ? 1 : 0;
  }
  EXPECT_GT(refused, 5);
  EXPECT_LT(refused, 55);
}

// A row far outside the pack (a slip in its exponent) would leave the engine's contact search
// without a grid, and so without any contact: refused, naming both rows.
TEST_F(ParticleFile, ARowBeyondTheSpanOfTheContactSearchIsRefused) {
  const std::string header = "x_m,y_m,z_m,diameter_m\n";
  const auto message =
      ErrorOf(Write("far.csv", header + "0,0,0.005,0.01\n0,0,2e12,0.01\n0.02,0,0.005,0.01\n"), 3);
  EXPECT_TRUE(Mentions(message, "far.csv:3")) << message;
  EXPECT_TRUE(Mentions(message, "along z from the particle on line 2")) << message;
  // Far, but within the span, reads: the grid widens its cells instead.
  EXPECT_EQ(
      ReadParticleFile(Write("far_ok.csv", header + "0,0,0.005,0.01\n0,0,5e11,0.01\n"), 3).size(),
      2u);
}

TEST_F(ParticleFile, HundredThousandParticleLatticeReads) {
  std::string text = "x_m,y_m,z_m,diameter_m\n";
  for (int i = 0; i < 100'000; ++i) {
    text += fmt::format("{},{},{},0.001\n", 0.001 * (i % 50), 0.001 * (i / 50 % 50),
                        0.001 * (i / 2500));
  }
  EXPECT_EQ(ReadParticleFile(Write("lattice.csv", text), 3).size(), 100'000u);
}

TEST_F(ParticleFile, ADirectoryIsRefusedAsAParticleFile) {
  const auto message = ErrorOf(folder_.path(), 3);
  EXPECT_TRUE(Mentions(message, ": is a directory, not a particle file")) << message;
}

TEST_F(ParticleFile, ParticlesOutsideTheContainerAreRefusedWithTheirLine) {
  const std::string header = "x_m,y_m,z_m,diameter_m\n";
  // Centre below the floor.
  auto message =
      ErrorOf(CylinderScene(Write("below.csv", header + "0,0.02,0.005,0.01\n0,0,-0.05,0.01\n"), 2));
  EXPECT_TRUE(Mentions(message,
                       "below.csv:3: particle at (0, 0, -0.05) lies outside the "
                       "container"))
      << message;
  // Beyond the side wall, also above the open top.
  message = ErrorOf(CylinderScene(Write("side.csv", header + "0.07,0,0.25,0.01\n"), 1));
  EXPECT_TRUE(Mentions(message, "side.csv:2: particle at (0.07, 0, 0.25) lies outside")) << message;
  // A settled pack presses into the walls by less than half a radius: accepted; more is not.
  EXPECT_EQ(
      ReadParticleFile(CylinderScene(Write("pressed.csv", header + "0.0460,0,0.0030,0.01\n"), 1))
          .size(),
      1u);
  message = ErrorOf(CylinderScene(Write("deep.csv", header + "0.0480,0,0.005,0.01\n"), 1));
  EXPECT_TRUE(Mentions(message, "deep.csv:2:")) << message;
  message = ErrorOf(CylinderScene(Write("sunk.csv", header + "0,0,0.0020,0.01\n"), 1));
  EXPECT_TRUE(Mentions(message, "sunk.csv:2:")) << message;
  // Above the rim of the open cylinder, inside its footprint: particles about to fall in.
  EXPECT_EQ(
      ReadParticleFile(CylinderScene(Write("above.csv", header + "0,0,0.5,0.01\n"), 1)).size(), 1u);
  // A LAMMPS file names its line too.
  message = ErrorOf(CylinderScene(
      Write("out.data", "LAMMPS data\n\n1 atoms\n\nAtoms # sphere\n\n1 1 0.01 7800 0 0 -0.05\n"),
      1));
  EXPECT_TRUE(Mentions(message, "out.data:7: particle at (0, 0, -0.05) lies outside")) << message;
}

TEST_F(ParticleFile, ABoxLidBoundsTheFileOnlyWhenClosed) {
  const auto path = Write("high.csv", "x_m,y_m,diameter_m\n0.001,0.0025,0.0001\n");
  Scene scene = CylinderScene(path, 1);
  scene.dimension = 2;
  scene.container.kind = ContainerKind::kBox;
  scene.container.min_m = {0, 0, 0};
  scene.container.max_m = {0.002, 0.002, 0};
  EXPECT_EQ(ReadParticleFile(scene).size(), 1u);
  scene.container.closed_top = true;
  const auto message = ErrorOf(scene);
  EXPECT_TRUE(Mentions(message, "high.csv:2: particle at (0.001, 0.0025) lies outside")) << message;
  EXPECT_TRUE(Mentions(message, "lid")) << message;
  // The side walls bound it at any height.
  scene.container.closed_top = false;
  scene.insertion.file = Write("left.csv", "x_m,y_m,diameter_m\n-0.0001,0.01,0.0001\n");
  EXPECT_TRUE(Mentions(ErrorOf(scene),
                       "left.csv:2: particle at (-0.0001, 0.01) lies outside the "
                       "container (its centre is at x = -0.0001 m, the side wall "
                       "at x = 0 m)"))
      << ErrorOf(scene);
}

TEST_F(ParticleFile, AParticleBehindAPlaneIsRefused) {
  Scene scene = CylinderScene(Write("plane.csv", "x_m,y_m,z_m,diameter_m\n0,0,-0.01,0.01\n"), 1);
  scene.container.kind = ContainerKind::kPlane;
  scene.container.point_m = {0, 0, 0};
  scene.container.normal = {0, 0, 2};  // not unit: the scene accepts any non-zero normal
  EXPECT_TRUE(Mentions(ErrorOf(scene), "plane.csv:2:"));
  scene.container.normal = {0, 0, -1};
  EXPECT_EQ(ReadParticleFile(scene).size(), 1u);
}

TEST_F(ParticleFile, UnknownSpeciesIsRefusedWithItsLine) {
  const auto message = ErrorOf(CylinderScene(
      Write("species.csv",
            "x_m,y_m,z_m,diameter_m,species\n0,0,0.005,0.01,0\n0.02,0,0.005,0.01,1\n"),
      2));
  EXPECT_TRUE(
      Mentions(message, "species.csv:3: names species 1 but the scene scene.json defines 1"))
      << message;
}

TEST_F(ParticleFile, TheFileMustHoldParticlesCount) {
  const auto path = Write("two.csv", "x_m,y_m,z_m,diameter_m\n0,0,0.005,0.01\n0.02,0,0.005,0.01\n");
  EXPECT_EQ(ReadParticleFile(CylinderScene(path, 2)).size(), 2u);
  const auto message = ErrorOf(CylinderScene(path, 100));
  EXPECT_TRUE(Mentions(message, "scene.json: particles.count: 100 particles, but "));
  EXPECT_TRUE(Mentions(message, "two.csv holds 2")) << message;
}

}  // namespace
}  // namespace bouncecal::dem::scene
