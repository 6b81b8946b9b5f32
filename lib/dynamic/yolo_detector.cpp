#include "dynamic/yolo_detector.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/data_paths.h"
#include "core/errors.h"
#include "core/timing.h"

namespace dynslam {
namespace fs = std::filesystem;

YoloLayout parseYoloLayout(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "auto" || n.empty()) return YoloLayout::Auto;
  if (n == "yolov5") return YoloLayout::YoloV5;
  if (n == "yolox") return YoloLayout::YoloX;
  throw std::invalid_argument("unknown detector layout '" + name +
                              "' (expected auto, yolov5 or yolox)");
}

const char* yoloLayoutName(YoloLayout layout) {
  switch (layout) {
    case YoloLayout::YoloV5:
      return "yolov5";
    case YoloLayout::YoloX:
      return "yolox";
    default:
      return "auto";
  }
}

// ---------------------------------------------------------------------------
// Minimal protobuf walk over an ONNX ModelProto, only to read the declared
// input shape: OpenCV 4.6 does not expose it after readNetFromONNX, and the
// blob must be allocated at that size before the first frame.
namespace {

struct PbReader {
  const unsigned char* p;
  const unsigned char* end;
  bool ok = true;

  bool atEnd() const { return !ok || p >= end; }
  uint64_t varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (p >= end) {
        ok = false;
        return 0;
      }
      const unsigned char b = *p++;
      v |= uint64_t(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    ok = false;
    return 0;
  }
  // Reads a field header; for length-delimited fields sets `sub` to the payload.
  bool next(int& field, int& wire, PbReader& sub) {
    const uint64_t key = varint();
    if (!ok) return false;
    field = int(key >> 3);
    wire = int(key & 7);
    switch (wire) {
      case 0:
        varint();
        break;
      case 1:
        if (end - p < 8)
          ok = false;
        else
          p += 8;
        break;
      case 5:
        if (end - p < 4)
          ok = false;
        else
          p += 4;
        break;
      case 2: {
        const uint64_t len = varint();
        if (!ok || uint64_t(end - p) < len) {
          ok = false;
          break;
        }
        sub = PbReader{p, p + len};
        p += len;
        break;
      }
      default:
        ok = false;
    }
    return ok;
  }
};

// For wire type 0 fields we need the value: re-read it.
uint64_t readVarintField(const unsigned char* start, const unsigned char* end) {
  PbReader r{start, end};
  r.varint();  // key
  return r.varint();
}

}  // namespace

std::vector<long long> readOnnxInputShape(const std::string& path) {
  return onnxInputShape(readRegularFile(path, kOnnxModelWhat), path);
}

std::vector<long long> onnxInputShape(const std::string& model_bytes, const std::string& path) {
  const auto* data = reinterpret_cast<const unsigned char*>(model_bytes.data());
  PbReader model{data, data + model_bytes.size()};
  PbReader graph{nullptr, nullptr};
  bool have_graph = false;
  int field, wire;
  PbReader sub{nullptr, nullptr};
  while (!model.atEnd() && model.next(field, wire, sub)) {
    if (field == 7 && wire == 2) {
      graph = sub;
      have_graph = true;
    }
  }
  if (!model.ok || !have_graph)
    throw InputError(path, "not an ONNX model (no graph in the protobuf)");

  std::set<std::string> initializers;
  std::vector<std::pair<std::string, std::vector<long long>>> inputs;
  while (!graph.atEnd() && graph.next(field, wire, sub)) {
    if (field == 5 && wire == 2) {  // TensorProto initializer: name = 8
      PbReader t = sub, s{nullptr, nullptr};
      int f, w;
      while (!t.atEnd() && t.next(f, w, s))
        if (f == 8 && w == 2) initializers.emplace(reinterpret_cast<const char*>(s.p), s.end - s.p);
    } else if (field == 11 && wire == 2) {  // ValueInfoProto input
      PbReader vi = sub, s{nullptr, nullptr};
      std::string name;
      std::vector<long long> dims;
      int f, w;
      while (!vi.atEnd() && vi.next(f, w, s)) {
        if (f == 1 && w == 2) name.assign(reinterpret_cast<const char*>(s.p), s.end - s.p);
        if (f == 2 && w == 2) {  // TypeProto -> tensor_type(1) -> shape(2) -> dim(1)
          PbReader tp = s, s2{nullptr, nullptr};
          int f2, w2;
          while (!tp.atEnd() && tp.next(f2, w2, s2)) {
            if (f2 != 1 || w2 != 2) continue;
            PbReader tt = s2, s3{nullptr, nullptr};
            int f3, w3;
            while (!tt.atEnd() && tt.next(f3, w3, s3)) {
              if (f3 != 2 || w3 != 2) continue;
              PbReader shp = s3, s4{nullptr, nullptr};
              int f4, w4;
              while (!shp.atEnd() && shp.next(f4, w4, s4)) {
                if (f4 != 1 || w4 != 2) continue;
                long long v = -1;
                PbReader dim = s4, s5{nullptr, nullptr};
                int f5, w5;
                const unsigned char* before = dim.p;
                while (!dim.atEnd() && dim.next(f5, w5, s5)) {
                  if (f5 == 1 && w5 == 0) v = (long long)readVarintField(before, dim.end);
                  before = dim.p;
                }
                dims.push_back(v);
              }
            }
          }
        }
      }
      inputs.emplace_back(name, dims);
    }
  }
  if (!graph.ok) throw InputError(path, "not an ONNX model (corrupt graph)");
  for (const auto& [name, dims] : inputs)
    if (!initializers.count(name)) return dims;
  return {};
}

// ---------------------------------------------------------------------------

namespace {

std::vector<std::string> readClassNames(const std::string& path) {
  std::istringstream in(readRegularFile(path, "class-name list"));
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) names.push_back(line);
  }
  if (names.empty()) throw InputError(path, "no class names");
  return names;
}

// Cells of the three YOLO output grids (strides 8/16/32).
int gridCells(cv::Size in) {
  int n = 0;
  for (int s : {8, 16, 32}) n += (in.width / s) * (in.height / s);
  return n;
}

}  // namespace

YoloDetector::YoloDetector(const YoloDetectorParams& params) : params_(params) {
  if (params_.model_path.empty()) params_.model_path = findModelFile(kDefaultDetectorModel);
  const std::string& model = params_.model_path;

  // Read once: the shape is parsed from the same bytes that OpenCV loads, so
  // a folder or a pipe named as the model is refused before anything waits
  // on it.
  const std::string model_bytes = readRegularFile(model, kOnnxModelWhat);
  const auto dims = onnxInputShape(model_bytes, model);  // throws InputError on non-protobuf
  if (dims.size() != 4 || dims[1] != 3 || dims[2] <= 0 || dims[3] <= 0)
    throw InputError(model, "expected a fixed 1x3xHxW model input");
  input_size_ = cv::Size(int(dims[3]), int(dims[2]));

  try {
    net_ = cv::dnn::readNetFromONNX(model_bytes.data(), model_bytes.size());
  } catch (const cv::Exception& e) {
    throw InputError(model, std::string("cannot load ONNX model: ") + e.what());
  }
  if (net_.empty()) throw InputError(model, "cannot load ONNX model");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);

  const std::string names_path = params_.class_names_path.empty()
                                     ? (fs::path(model).parent_path() / "coco.names").string()
                                     : params_.class_names_path;
  class_names_ = readClassNames(names_path);
  is_dynamic_.assign(class_names_.size(), 0);
  for (const auto& dyn : params_.dynamic_classes) {
    const auto it = std::find(class_names_.begin(), class_names_.end(), dyn);
    if (it == class_names_.end())
      throw InputError(names_path, "dynamic class '" + dyn + "' is not in the class list");
    is_dynamic_[it - class_names_.begin()] = 1;
  }

  // Allocate the per-frame buffers once and run one forward pass: it validates
  // the output layout now (clear error at start-up, not at frame 1) and makes
  // cv::dnn allocate its internal blobs.
  blob_.create(std::vector<int>{1, 3, input_size_.height, input_size_.width}, CV_32F);
  blob_.setTo(0);
  canvas_.create(input_size_, CV_8UC3);
  swapped_.create(input_size_, CV_8UC3);
  floats_.create(input_size_, CV_32FC3);
  try {
    net_.setInput(blob_);
    net_.forward(outputs_, net_.getUnconnectedOutLayersNames());
  } catch (const cv::Exception& e) {
    throw InputError(model, std::string("forward pass failed: ") + e.what());
  }
  if (outputs_.empty() || outputs_[0].dims != 3)
    throw InputError(model, "expected one 1xNx(5+classes) output");
  const int rows = outputs_[0].size[1];
  num_classes_ = outputs_[0].size[2] - 5;
  if (num_classes_ != int(class_names_.size()))
    throw InputError(model, "model has " + std::to_string(num_classes_) + " classes but " +
                                names_path + " lists " + std::to_string(class_names_.size()));
  const int cells = gridCells(input_size_);
  YoloLayout detected = YoloLayout::Auto;
  if (rows == 3 * cells)
    detected = YoloLayout::YoloV5;
  else if (rows == cells)
    detected = YoloLayout::YoloX;
  layout_ = params_.layout == YoloLayout::Auto ? detected : params_.layout;
  if (layout_ == YoloLayout::Auto)
    throw InputError(model, "cannot tell the output layout from " + std::to_string(rows) +
                                " rows; set the layout (yolov5 or yolox)");
  if (layout_ == YoloLayout::YoloX && rows != cells)
    throw InputError(model, "yolox layout needs " + std::to_string(cells) + " rows, model has " +
                                std::to_string(rows));
}

void YoloDetector::prepareInput(const cv::Mat& bgr) {
  image_size_ = bgr.size();
  if (bgr.size() == input_size_) {
    bgr.copyTo(canvas_);  // no reallocation: same size and type
    scale_x_ = scale_y_ = 1;
    pad_x_ = pad_y_ = 0;
  } else {
    // Letterbox: keep the aspect ratio, pad with grey 114 as in training.
    const double s =
        std::min(double(input_size_.width) / bgr.cols, double(input_size_.height) / bgr.rows);
    const int w = std::max(1, int(std::lround(bgr.cols * s)));
    const int h = std::max(1, int(std::lround(bgr.rows * s)));
    const int px = (input_size_.width - w) / 2, py = (input_size_.height - h) / 2;
    canvas_.setTo(cv::Scalar::all(114));
    cv::Mat roi = canvas_(cv::Rect(px, py, w, h));
    cv::resize(bgr, roi, roi.size(), 0, 0, cv::INTER_LINEAR);
    scale_x_ = double(w) / bgr.cols;
    scale_y_ = double(h) / bgr.rows;
    pad_x_ = px;
    pad_y_ = py;
  }
  const cv::Mat* src = &canvas_;
  double alpha = 1.0;
  if (layout_ == YoloLayout::YoloV5) {  // RGB, 0..1
    cv::cvtColor(canvas_, swapped_, cv::COLOR_BGR2RGB);
    src = &swapped_;
    alpha = 1.0 / 255.0;
  }
  src->convertTo(floats_, CV_32F, alpha);
  // Split HWC into the CHW planes of the preallocated blob (headers only).
  const int H = input_size_.height, W = input_size_.width;
  cv::Mat planes[3];
  for (int c = 0; c < 3; ++c) planes[c] = cv::Mat(H, W, CV_32F, blob_.ptr<float>(0, c));
  cv::split(floats_, planes);
}

void YoloDetector::decode(const cv::Mat& out, std::vector<cv::Rect2f>& boxes,
                          std::vector<float>& scores, std::vector<int>& classes) const {
  const int rows = out.size[1], cols = out.size[2];
  const float* data = out.ptr<float>();
  const float conf = params_.conf_threshold;

  auto consider = [&](const float* r, float cx, float cy, float w, float h) {
    const float obj = r[4];
    if (obj < conf) return;
    const float* cls = r + 5;
    int best = 0;
    if (params_.only_dynamic) {
      best = -1;
      for (int c = 0; c < num_classes_; ++c)
        if (is_dynamic_[c] && (best < 0 || cls[c] > cls[best])) best = c;
      if (best < 0) return;
    } else {
      best = int(std::max_element(cls, cls + num_classes_) - cls);
    }
    const float score = obj * cls[best];
    if (score < conf) return;
    // Input pixels -> image pixels (undo the letterbox).
    const float x0 = float(((cx - 0.5f * w) - pad_x_) / scale_x_);
    const float y0 = float(((cy - 0.5f * h) - pad_y_) / scale_y_);
    boxes.emplace_back(x0, y0, float(w / scale_x_), float(h / scale_y_));
    scores.push_back(score);
    classes.push_back(best);
  };

  if (layout_ == YoloLayout::YoloV5) {
    for (int i = 0; i < rows; ++i) {
      const float* r = data + std::size_t(i) * cols;
      consider(r, r[0], r[1], r[2], r[3]);
    }
  } else {
    int i = 0;
    for (int stride : {8, 16, 32}) {
      const int gw = input_size_.width / stride, gh = input_size_.height / stride;
      for (int gy = 0; gy < gh; ++gy)
        for (int gx = 0; gx < gw; ++gx, ++i) {
          const float* r = data + std::size_t(i) * cols;
          if (r[4] < conf) continue;  // cheap reject before exp()
          consider(r, (r[0] + gx) * stride, (r[1] + gy) * stride, std::exp(r[2]) * stride,
                   std::exp(r[3]) * stride);
        }
    }
  }
}

std::vector<Detection> YoloDetector::detect(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("YoloDetector::detect: expected a BGR CV_8UC3 image");
  prepareInput(bgr);

  const auto t0 = SteadyClock::now();
  net_.setInput(blob_);
  net_.forward(outputs_, net_.getUnconnectedOutLayersNames());
  last_forward_ms_ = msSince(t0);

  std::vector<cv::Rect2f> boxes;
  std::vector<float> scores;
  std::vector<int> classes;
  decode(outputs_[0], boxes, scores, classes);

  // Class-aware NMS in one call: shift each class to its own far-away region
  // so boxes of different classes never overlap (same result as per-class NMS).
  const double offset = 4.0 * std::max(image_size_.width, image_size_.height) + 1.0;
  std::vector<cv::Rect2d> shifted(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const auto& b = boxes[i];
    shifted[i] = cv::Rect2d(b.x + classes[i] * offset, b.y, b.width, b.height);
  }
  std::vector<int> keep;
  cv::dnn::NMSBoxes(shifted, scores, params_.conf_threshold, params_.nms_iou, keep);

  const cv::Rect2f frame(0, 0, float(image_size_.width), float(image_size_.height));
  std::vector<Detection> dets;
  dets.reserve(keep.size());
  for (int k : keep) {
    Detection d;
    d.box = boxes[k] & frame;
    if (d.box.width <= 0 || d.box.height <= 0) continue;
    d.class_id = classes[k];
    d.score = scores[k];
    d.dynamic_class = is_dynamic_[classes[k]] != 0;
    if (params_.only_dynamic && !d.dynamic_class) continue;
    dets.push_back(d);
  }
  std::sort(dets.begin(), dets.end(),
            [](const Detection& a, const Detection& b) { return a.score > b.score; });
  return dets;
}

}  // namespace dynslam
