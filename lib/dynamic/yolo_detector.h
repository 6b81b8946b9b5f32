#pragma once
// Object detector for the dynamic-object filter: finds people (and any other
// class configured as "dynamic") so the tracker can ignore their keypoints.
//
// Why YOLO through cv::dnn: OpenCV 4.6 is already a dependency, it reads the
// shipped ONNX models (see ../shared/models/README.md) and needs no GPU. Two
// output layouts are supported because the two model families we ship differ:
//   - YOLOv5 ("yolov5"): 1xNx85 rows already decoded (cx cy w h in input
//     pixels, objectness, 80 class probabilities); input RGB scaled to 0..1.
//   - YOLOX ("yolox"): 1xNx85 raw head; x,y = (p + grid) * stride and
//     w,h = exp(p) * stride over strides 8/16/32; input BGR 0..255.
// The layout is detected from the row count (YOLOv5 has 3 anchors per grid
// cell, YOLOX one) unless set explicitly.
//
// Cost: a forward pass is ~50-100 ms on 2 cores, so detection cannot run on
// every frame of a 30 Hz tracker; the caller decides when to call detect().
// The input blob is allocated once and reused, so detect() does not allocate
// multi-MB buffers per frame (the forward pass itself reuses cv::dnn's
// internal buffers).
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include <string>
#include <vector>

namespace dynslam {

struct Detection {
  cv::Rect2f box;              ///< image pixels (of the image given to detect())
  int class_id = -1;           ///< index into the class-name list (COCO: 0 = person)
  float score = 0;             ///< objectness x class probability
  bool dynamic_class = false;  ///< class is in YoloDetectorParams::dynamic_classes
};

/// The default model (TUM frame size, so no letterbox is needed), looked up
/// in the models folders when YoloDetectorParams::model_path is empty.
inline constexpr const char* kDefaultDetectorModel = "yolov5n_480x640.onnx";

enum class YoloLayout { Auto, YoloV5, YoloX };

/// "auto", "yolov5", "yolox" (case-insensitive); throws std::invalid_argument.
YoloLayout parseYoloLayout(const std::string& name);
const char* yoloLayoutName(YoloLayout layout);

struct YoloDetectorParams {
  /// ONNX model; empty = kDefaultDetectorModel found by findModelFile
  /// (core/data_paths.h: $DYNSLAM_MODELS_DIR, ...).
  std::string model_path;
  /// One class name a line; empty = coco.names next to the model.
  std::string class_names_path;
  YoloLayout layout = YoloLayout::Auto;
  /// Minimum objectness x class probability.
  float conf_threshold = 0.25f;
  /// IoU above which a lower-scoring box of the same class is suppressed.
  float nms_iou = 0.45f;
  /// Classes whose objects may move; their detections get dynamic_class=true.
  std::vector<std::string> dynamic_classes{"person"};
  /// Return only detections of dynamic classes (what the SLAM filter needs).
  bool only_dynamic = false;
};

class YoloDetector {
 public:
  /// Loads the model and class names. Throws InputError naming the file when
  /// the model is missing or not a readable ONNX network, the class list is
  /// unreadable, a dynamic class name is unknown, or the output layout is not
  /// one of the two supported ones.
  explicit YoloDetector(const YoloDetectorParams& params = {});

  /// Detects objects in a BGR CV_8UC3 image of any size (letterboxed when its
  /// size differs from the model input). Boxes are in image coordinates,
  /// clipped to the image, sorted by decreasing score.
  std::vector<Detection> detect(const cv::Mat& bgr);

  cv::Size inputSize() const { return input_size_; }
  YoloLayout layout() const { return layout_; }
  const std::vector<std::string>& classNames() const { return class_names_; }
  const YoloDetectorParams& params() const { return params_; }
  /// Duration of the last cv::dnn forward pass alone (ms), for benchmarks.
  double lastForwardMs() const { return last_forward_ms_; }

 private:
  void prepareInput(const cv::Mat& bgr);
  void decode(const cv::Mat& out, std::vector<cv::Rect2f>& boxes, std::vector<float>& scores,
              std::vector<int>& classes) const;

  YoloDetectorParams params_;
  cv::dnn::Net net_;
  std::vector<std::string> class_names_;
  std::vector<char> is_dynamic_;  // per class id
  YoloLayout layout_ = YoloLayout::Auto;
  cv::Size input_size_;
  int num_classes_ = 80;

  // Per-frame buffers, allocated once (sizes only change with the image size).
  cv::Mat canvas_;   // CV_8UC3 model-size image (resized / letterboxed)
  cv::Mat swapped_;  // CV_8UC3 channel-swapped copy (YOLOv5 wants RGB)
  cv::Mat floats_;   // CV_32FC3
  cv::Mat blob_;     // 1x3xHxW CV_32F, fed to the network
  std::vector<cv::Mat> outputs_;
  // Mapping of the last prepared frame: image = (input - pad) / scale.
  double scale_x_ = 1, scale_y_ = 1, pad_x_ = 0, pad_y_ = 0;
  cv::Size image_size_;
  double last_forward_ms_ = 0;
};

/// What an ONNX model file is called in errors ("is a folder, expected a ...").
inline const std::string kOnnxModelWhat = "YOLO model (ONNX)";

/// The (N, C, H, W) input shape stored in an ONNX model's bytes (first graph
/// input that is not an initializer). Returns an empty vector when the model
/// has none with fixed dims. Throws InputError naming path when the bytes are
/// not a protobuf.
std::vector<long long> onnxInputShape(const std::string& model_bytes, const std::string& path);
/// The same, read from the file (refused unless it is a regular file).
std::vector<long long> readOnnxInputShape(const std::string& path);

}  // namespace dynslam
