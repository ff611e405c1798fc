// Bad input: each error names the file (and field), and the manifest round-trips.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {
namespace {

namespace fs = std::filesystem;

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(RAMTK_TEST_OUTPUT_DIR) /
           ("bad_input_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  // A 4-step, one-cycle set of 8-bit images img0..img3.png (valid).
  FringeManifest WriteGoodSet(int bits = 8) {
    FringeManifest m;
    m.path = (dir_ / "manifest.json").string();
    m.projector_width = 64;
    m.projector_height = 48;
    SequenceBlock ps;
    ps.steps = 4;
    ps.cycles = {1};
    m.sequence.push_back(ps);
    for (int k = 0; k < 4; ++k) {
      cv::Mat img(24, 32, bits == 8 ? CV_8U : CV_16U);
      for (int x = 0; x < img.cols; ++x)
        for (int y = 0; y < img.rows; ++y) {
          const double v = 0.5 + 0.4 * std::cos(2 * M_PI * x / 32.0 - M_PI + 2 * M_PI * k / 4);
          if (bits == 8)
            img.at<uchar>(y, x) = cv::saturate_cast<uchar>(v * 255);
          else
            img.at<uint16_t>(y, x) = cv::saturate_cast<uint16_t>(v * 65535);
        }
      const std::string name = "img" + std::to_string(k) + ".png";
      WriteImage((dir_ / name).string(), img);
      m.cameras["cam"].push_back(name);
    }
    WriteFringeManifest(m.path, m);
    return m;
  }
  std::string ErrorOf(const FringeManifest& m) {
    try {
      DecodeCamera(m, "cam", DecodeOptions{});
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(BadInput, GoodSetDecodes) {
  const FringeManifest m = ReadFringeManifest(WriteGoodSet().path);
  const DecodedCamera d = DecodeCamera(m, "cam", DecodeOptions{});
  EXPECT_GT(d.summary.valid_fraction, 0.99);
  // One period across the projector: coordinate = 2 * camera x (64 px projector over 32 px camera).
  EXPECT_NEAR(d.coordinate.at<float>(10, 7), 14.0, 0.2);
}

TEST_F(BadInput, MissingImageIsNamed) {
  FringeManifest m = WriteGoodSet();
  fs::remove(dir_ / "img2.png");
  EXPECT_NE(ErrorOf(m).find("img2.png: image file does not exist"), std::string::npos) << ErrorOf(m);
}

TEST_F(BadInput, UnreadableImageIsNamed) {
  FringeManifest m = WriteGoodSet();
  std::ofstream(dir_ / "img1.png") << "not a png";
  EXPECT_NE(ErrorOf(m).find("img1.png"), std::string::npos) << ErrorOf(m);
}

TEST_F(BadInput, MixedSizesAreNamed) {
  FringeManifest m = WriteGoodSet();
  WriteImage((dir_ / "img3.png").string(), cv::Mat(20, 32, CV_8U, cv::Scalar(100)));
  const std::string e = ErrorOf(m);
  EXPECT_NE(e.find("img3.png: image is 32x20"), std::string::npos) << e;
}

TEST_F(BadInput, MixedBitDepthsAreNamed) {
  FringeManifest m = WriteGoodSet();
  WriteImage((dir_ / "img1.png").string(), cv::Mat(24, 32, CV_16U, cv::Scalar(30000)));
  const std::string e = ErrorOf(m);
  EXPECT_NE(e.find("img1.png: 16-bit image in a set of 8-bit images"), std::string::npos) << e;
}

TEST_F(BadInput, AllDarkSetIsNamed) {
  FringeManifest m = WriteGoodSet();
  for (int k = 0; k < 4; ++k)
    WriteImage((dir_ / ("img" + std::to_string(k) + ".png")).string(), cv::Mat(24, 32, CV_8U, cv::Scalar(2)));
  const std::string e = ErrorOf(m);
  EXPECT_NE(e.find("img0.png: all 4 images are dark"), std::string::npos) << e;
}

TEST_F(BadInput, SixteenBitSetDecodes) {
  const FringeManifest m = ReadFringeManifest(WriteGoodSet(16).path);
  const DecodedCamera d = DecodeCamera(m, "cam", DecodeOptions{});
  EXPECT_GT(d.summary.valid_fraction, 0.99);
  EXPECT_NEAR(d.coordinate.at<float>(3, 20), 40.0, 0.05);
}

TEST_F(BadInput, SequenceImageCountMismatchNamesManifestAndCamera) {
  FringeManifest m = WriteGoodSet();
  m.cameras["cam"].pop_back();
  WriteFringeManifest(m.path, m);
  try {
    ReadFringeManifest(m.path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, m.path);
    EXPECT_EQ(e.where().field, "cameras.cam");
    EXPECT_NE(std::string(e.what()).find("needs 4 images, the camera lists 3"), std::string::npos) << e.what();
  }
}

TEST_F(BadInput, ManifestFieldErrors) {
  const std::string path = (dir_ / "m.json").string();
  auto error_for = [&](const std::string& text) -> std::string {
    std::ofstream(path) << text;
    try {
      ReadFringeManifest(path);
    } catch (const InputError& e) {
      return e.where().field + " | " + e.what();
    }
    return "";
  };
  const std::string head = R"({"projector": {"width": 1024, "height": 768}, "direction": "vertical", )";
  EXPECT_NE(error_for(head +
                      R"("sequence": [{"type": "phase_shift", "steps": 2, "cycles": 1}], "cameras": {"c": ["a","b"]}})")
                .find("sequence[0].steps"),
            std::string::npos);
  EXPECT_NE(
      error_for(
          head +
          R"("sequence": [{"type": "phase_shift", "steps": 4, "cycles": 32}, {"type": "gray_code", "bits": 5, "complementary": true}], "cameras": {"c": []}})")
          .find("bits = log2(cycles)+1"),
      std::string::npos);
  EXPECT_NE(error_for(head + R"("sequence": [{"type": "spiral"}], "cameras": {}})").find("sequence[0].type"),
            std::string::npos);
  EXPECT_NE(error_for(R"({"projector": {"width": 1024}})").find("projector.height"), std::string::npos);
  EXPECT_NE(error_for("{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(
      error_for(head +
                R"("sequence": [{"type": "heterodyne", "steps": 4, "cycles": [64, 59, 50]}], "cameras": {"c": []}})")
          .find("beat"),
      std::string::npos);
}

TEST_F(BadInput, ManifestRoundTrip) {
  FringeManifest m = WriteGoodSet();
  SequenceBlock h;
  h.type = BlockType::kHeterodyne;
  h.steps = 4;
  h.cycles = {64, 60, 57};
  h.phase_at_origin_rad = 0.5;
  m.sequence = {h};
  m.direction = FringeDirection::kHorizontal;
  m.projector_height = 768;
  m.calibration = "calib.yml";
  m.cameras = {{"left", std::vector<std::string>(12, "l.png")}, {"right", std::vector<std::string>(12, "r.png")}};
  WriteFringeManifest(m.path, m);
  const FringeManifest r = ReadFringeManifest(m.path);
  EXPECT_EQ(FringeManifestToJson(r), FringeManifestToJson(m));
  EXPECT_EQ(r.Extent(), 768);
  EXPECT_NEAR(r.sequence[0].phase_at_origin_rad, 0.5, 1e-12);
  EXPECT_EQ(r.Resolve("l.png"), (dir_ / "l.png").string());
}

TEST_F(BadInput, PeriodInPixelsIsConvertedToCycles) {
  const std::string path = (dir_ / "p.json").string();
  std::ofstream(path) << R"({"projector": {"width": 912, "height": 1140}, "direction": "horizontal",
    "sequence": [{"type": "phase_shift", "steps": 3, "period_px": 1140}], "cameras": {"c": ["a", "b", "c"]}})";
  const FringeManifest m = ReadFringeManifest(path);
  EXPECT_DOUBLE_EQ(m.sequence[0].cycles[0], 1.0);
}

TEST(DecodeOptions, ValidateNamesTheField) {
  DecodeOptions o;
  o.saturation_fraction = 1.5;
  EXPECT_EQ(SplitOptionsProblem(o.Validate()).field, "saturation_fraction");
  try {
    ThrowIfInvalid(o.Validate(), "DecodeOptions");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "saturation_fraction");
  }
  DecodeOptions sampling;
  sampling.estimate_max_samples = -1;
  EXPECT_EQ(SplitOptionsProblem(sampling.Validate()).field, "estimate_max_samples");
  sampling.estimate_max_samples = 0;  // the strides alone
  EXPECT_EQ(sampling.Validate(), "");
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

TEST(DecodeProgress, CallbackSeesStagesAndCanCancel) {
  FringeManifest m;
  m.projector_width = 64;
  m.projector_height = 8;
  SequenceBlock ps;
  ps.steps = 4;
  ps.cycles = {1};
  m.sequence.push_back(ps);
  m.cameras["cam"].resize(4);
  std::vector<cv::Mat> frames;
  for (int k = 0; k < 4; ++k) {
    cv::Mat f(8, 64, CV_32F);
    for (int x = 0; x < 64; ++x) f.col(x).setTo(128 + 100 * std::cos(2 * M_PI * x / 64 - M_PI + 2 * M_PI * k / 4));
    frames.push_back(f);
  }
  DecodeOptions opt;
  std::vector<std::string> stages;
  opt.progress = [&](const Progress& p) {
    stages.push_back(p.stage);
    return true;
  };
  EXPECT_EQ(DecodeFrames(m, frames, 255.0, opt).summary.termination, Termination::kSuccess);
  EXPECT_EQ(stages, (std::vector<std::string>{"phase", "unwrap", "nonlinearity", "done"}));
  opt.progress = [](const Progress& p) { return p.stage != "unwrap"; };
  EXPECT_EQ(DecodeFrames(m, frames, 255.0, opt).summary.termination, Termination::kCancelled);
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

// Image loading: PNG and BMP through ramtk's own codecs (image/), TIFF through the OpenImageIO backend
// module (loaded on first use); every path gives the pixel values that were written.
class ImageLoading : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(RAMTK_TEST_OUTPUT_DIR) / "image_loading";
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    grey8_.create(37, 53, CV_8UC1);
    grey16_.create(37, 53, CV_16UC1);
    colour8_.create(37, 53, CV_8UC3);
    for (int y = 0; y < 37; ++y)
      for (int x = 0; x < 53; ++x) {
        grey8_.at<uchar>(y, x) = static_cast<uchar>((7 * x + 13 * y) % 256);
        grey16_.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>((977 * x + 3001 * y) % 65536);
        colour8_.at<cv::Vec3b>(y, x) = cv::Vec3b(x % 256, y % 256, (x + y) % 256);
      }
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
  cv::Mat grey8_, grey16_, colour8_;
};

double MaxDiff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  return cv::norm(fa, fb, cv::NORM_INF);
}

TEST_F(ImageLoading, EveryFormatGivesTheWrittenValues) {
  for (const std::string ext : {".png", ".bmp", ".tif"}) {
    SCOPED_TRACE(ext);
    WriteImage(Path("g8" + ext), grey8_);
    int bits = 0;
    const cv::Mat native = LoadImageNative(Path("g8" + ext), &bits);
    EXPECT_EQ(bits, 8);
    EXPECT_EQ(native.type(), CV_8UC1);
    EXPECT_EQ(MaxDiff(native, grey8_), 0.0);
    const cv::Mat dn = LoadImageDn(Path("g8" + ext), &bits);
    EXPECT_EQ(dn.type(), CV_32FC1);
    EXPECT_EQ(MaxDiff(dn, grey8_), 0.0);
  }
  for (const std::string ext : {".png", ".tif"}) {  // BMP has no 16-bit grey
    SCOPED_TRACE(ext);
    WriteImage(Path("g16" + ext), grey16_);
    int bits = 0;
    EXPECT_EQ(MaxDiff(LoadImageNative(Path("g16" + ext), &bits), grey16_), 0.0);
    EXPECT_EQ(bits, 16);
    EXPECT_EQ(MaxDiff(LoadImageDn(Path("g16" + ext), &bits), grey16_), 0.0);
  }
  // Colour: the mean of the three channels, in DN (the order of the channels does not matter).
  cv::Mat mean(colour8_.rows, colour8_.cols, CV_64F);
  for (int y = 0; y < colour8_.rows; ++y)
    for (int x = 0; x < colour8_.cols; ++x) {
      const cv::Vec3b v = colour8_.at<cv::Vec3b>(y, x);
      mean.at<double>(y, x) = (v[0] + v[1] + v[2]) / 3.0;
    }
  for (const std::string ext : {".png", ".tif"}) {
    SCOPED_TRACE(ext);
    WriteImage(Path("c8" + ext), colour8_);
    int bits = 0;
    EXPECT_LE(MaxDiff(LoadImageDn(Path("c8" + ext), &bits), mean), 1.0 / 32);  // rounded to 1/16 DN
    EXPECT_LE(MaxDiff(LoadImageNative(Path("c8" + ext), &bits), mean), 1.0 / 32);
  }
}

TEST_F(ImageLoading, HostileHeaderIsRefusedBeforeAllocation) {
  // A 33-byte PNG whose header claims 1 000 000 x 1 000 000 pixels.
  const unsigned char png[] = {0x89, 'P',  'N',  'G',  '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 0x00,
                               0x0f, 0x42, 0x40, 0x00, 0x0f, 0x42, 0x40, 8,    0, 0, 0, 0,  0,   0,   0,   0};
  std::ofstream(Path("huge.png"), std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof(png));
  try {
    int bits = 0;
    LoadImageNative(Path("huge.png"), &bits);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1000000 x 1000000"), std::string::npos) << e.what();
    EXPECT_EQ(e.where().file, Path("huge.png"));
  }
}

}  // namespace
}  // namespace ramtk::vision
