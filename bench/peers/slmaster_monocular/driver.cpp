// Timing and output driver for SLMaster's monocular (camera + projector) CPU path, following
// src/cameras/monocular/monocularCamera.cpp MonocularCamera::decode with
// MonoSinusCompleGrayCodePattern::decode and gui/src/CameraEngine.cpp's parameters for its
// monocular SinusCompleGrayCode pattern (gui/qml/res/config/monocularCameraConfig.json: 12 phase
// shifts, 32 cycles, vertical, DLP 1920x1024, contrast threshold 60, depth 0..1500 mm, noise
// filter on):
//   texture map -> confidence, wrapped phase, floor (complementary Gray code), unwrap ->
//   reverseCamera (PL1 = M1, PR4 = M4 [Rlp | Tlp], pitch = 1920 / 32) -> bilateralFilter(15, 20, 50)
//   -> fromDepthMapToCloud.
// Our code; it calls SLMaster's library built outside the repository (build.sh).
//
// usage: driver [--data DIR] [--out cloud.ply] [--reps N]
//   prints one line: load, pipeline and total ms (the first run), valid depth pixels, cloud points;
//   with --reps N also the median pipeline time of N runs on the loaded images.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/core/eigen.hpp>
#include <opencv2/opencv.hpp>

#include "algorithm/cpuStructuredLight/recoverDepth.h"
#include "algorithm/cpuStructuredLight/sinusCompleGraycodePattern.hpp"
#include "cameras/caliInfo.h"
#include "cameras/tool.h"

using Clock = std::chrono::steady_clock;
static double ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

static const int kShift = 12, kCycles = 32, kFrames = 18, kWidth = 1920, kHeight = 1024;

struct Run {
    long valid = 0, points = 0;
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
};

static Run pipeline(const std::vector<cv::Mat> &imgs, const slmaster::cameras::CaliInfo &cali) {
    Run r;
    const auto &in = cali.info_;
    // CameraEngine: PL1 = M1 (4x4), PR4 = M4 * [Rlp | Tlp].
    cv::Mat PL1 = cv::Mat::eye(4, 4, CV_32FC1);
    in.M1_.copyTo(PL1(cv::Rect(0, 0, 3, 3)));
    cv::Mat PR4 = cv::Mat::eye(4, 4, CV_32FC1);
    in.Rlp_.copyTo(PR4(cv::Rect(0, 0, 3, 3)));
    in.Tlp_.copyTo(PR4(cv::Rect(3, 0, 1, 3)));
    cv::Mat M4 = cv::Mat::eye(4, 4, CV_32FC1);
    in.M4_.copyTo(M4(cv::Rect(0, 0, 3, 3)));
    PR4 = M4 * PR4;
    Eigen::Matrix4f pl, pr;
    cv::cv2eigen(PL1, pl);
    cv::cv2eigen(PR4, pr);
    // MonocularCamera::decode: texture map.
    cv::Mat texture = cv::Mat::zeros(imgs[0].size(), imgs[0].type());
    for (int i = 0; i < kShift; ++i) texture += imgs[i] / kShift;
    cv::cvtColor(texture, texture, cv::COLOR_GRAY2BGR);
    // MonoSinusCompleGrayCodePattern::decode (CPU).
    slmaster::algorithm::SinusCompleGrayCodePattern::Params p;
    p.shiftTime = kShift;
    p.confidenceThreshold = 60.f;
    p.width = kWidth;
    p.height = kHeight;
    p.nbrOfPeriods = kCycles;
    p.horizontal = false;
    auto pattern = slmaster::algorithm::SinusCompleGrayCodePattern::create(p);
    cv::Mat wrapped, confidence, floorMap, unwrapped, depth;
    pattern->computePhaseMap(imgs, wrapped);
    pattern->computeConfidenceMap(imgs, confidence);
    pattern->computeFloorMap(imgs, confidence, wrapped, floorMap);
    pattern->unwrapPhaseMap(wrapped, floorMap, confidence, unwrapped);
    slmaster::algorithm::reverseCamera(unwrapped, pl, pr, 0.f, 1500.f, static_cast<float>(kWidth) / kCycles, depth,
                                       false);
    // Noise Filter (on in SLMaster's monocular configuration).
    cv::bilateralFilter(depth.clone(), depth, 15, 20, 50);
    cv::Mat depthOut;
    slmaster::cameras::fromDepthMapToCloud(depth, texture, cali, r.cloud, depthOut, false);
    r.valid = cv::countNonZero(depth > 0.001f);
    r.points = static_cast<long>(r.cloud.size());
    return r;
}

static void writePly(const std::string &path, const pcl::PointCloud<pcl::PointXYZRGB> &cloud) {
    std::ofstream f(path, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\ncomment SLMaster monocular path (bench/peers/slmaster_monocular)\n"
      << "element vertex " << cloud.size() << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (const auto &q : cloud.points) {
        const float xyz[3] = {q.x, q.y, q.z};
        f.write(reinterpret_cast<const char *>(xyz), sizeof xyz);
    }
}

int main(int argc, char **argv) {
    std::string dir = "../shared/data/slmaster-monocular", out;
    int reps = 0;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--data") && i + 1 < argc) dir = argv[++i];
        else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
        else if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::atoi(argv[++i]);
        else { std::fprintf(stderr, "usage: %s [--data DIR] [--out cloud.ply] [--reps N]\n", argv[0]); return 2; }
    }
    const auto t0 = Clock::now();
    slmaster::cameras::CaliInfo cali(dir + "/caliInfo.yml");
    std::vector<cv::Mat> imgs(kFrames);
    for (int i = 0; i < kFrames; ++i) {
        imgs[i] = cv::imread(dir + "/L/" + std::to_string(i) + ".bmp", cv::IMREAD_UNCHANGED);
        if (imgs[i].empty() || imgs[i].type() != CV_8UC1) { std::fprintf(stderr, "cannot read image %d\n", i); return 1; }
    }
    const auto t1 = Clock::now();
    Run r = pipeline(imgs, cali);
    const auto t2 = Clock::now();
    std::printf("load %.1f ms, pipeline %.1f ms, total %.1f ms, valid depth pixels %ld, cloud %ld\n", ms(t0, t1),
                ms(t1, t2), ms(t0, t2), r.valid, r.points);
    if (!out.empty()) writePly(out, r.cloud);
    if (reps > 0) {
        std::vector<double> v;
        for (int k = 0; k < reps; ++k) {
            const auto a = Clock::now();
            pipeline(imgs, cali);
            v.push_back(ms(a, Clock::now()));
        }
        std::sort(v.begin(), v.end());
        std::printf("pipeline on loaded images, %d reps: min %.1f ms, median %.1f ms\n", reps, v.front(), v[v.size() / 2]);
    }
    return 0;
}
