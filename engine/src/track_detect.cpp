// Stage 1 of tracking: per-frame candidate blobs (docs/capture.md, "Detection").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <sys/stat.h>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "pteromys/track.hpp"

namespace pteromys::capture {
namespace {

// Frames decoded by a second thread into a small queue (decoding is about
// half the work; the machine has two cores).
class FrameReader {
 public:
  /// `feature` turns a decoded BGR frame into the 8-bit image the detector works on.
  FrameReader(cv::VideoCapture& cap, int last_needed, std::function<void(const cv::Mat&, cv::Mat&)> feature)
      : cap_(cap), last_(last_needed), feature_(std::move(feature)), worker_([this] { run(); }) {}
  ~FrameReader() {
    {
      std::lock_guard<std::mutex> l(m_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  // Next frame; false at the end of the video (or after last_needed).
  bool next(int& index, cv::Mat& img) {
    std::unique_lock<std::mutex> l(m_);
    cv_.wait(l, [this] { return !q_.empty() || done_; });
    if (q_.empty()) return false;
    index = q_.front().first;
    img = std::move(q_.front().second);
    q_.pop_front();
    cv_.notify_all();
    return true;
  }

 private:
  void run() {
    int i = 0;
    cv::Mat f, g;
    while (true) {
      {
        std::unique_lock<std::mutex> l(m_);
        cv_.wait(l, [this] { return q_.size() < 6 || stop_; });
        if (stop_) break;
      }
      if (last_ >= 0 && i > last_) break;
      if (!cap_.read(f) || f.empty()) break;
      cv::Mat bgr, out;
      if (f.channels() == 1) cv::cvtColor(f, bgr, cv::COLOR_GRAY2BGR);
      else if (f.channels() == 4) cv::cvtColor(f, bgr, cv::COLOR_BGRA2BGR);
      else bgr = f;
      feature_(bgr, out);
      {
        std::lock_guard<std::mutex> l(m_);
        q_.emplace_back(i, std::move(out));
      }
      cv_.notify_all();
      ++i;
    }
    std::lock_guard<std::mutex> l(m_);
    done_ = true;
    cv_.notify_all();
  }

  cv::VideoCapture& cap_;
  int last_;
  std::function<void(const cv::Mat&, cv::Mat&)> feature_;
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<std::pair<int, cv::Mat>> q_;
  bool stop_ = false, done_ = false;
  std::thread worker_;
};

// Per-pixel median of 8-bit single-channel images.
cv::Mat median_of(const std::vector<const cv::Mat*>& imgs) {
  const int k = static_cast<int>(imgs.size());
  cv::Mat out(imgs[0]->size(), CV_8U);
  const int rows = out.rows, cols = out.cols;
  std::vector<const uchar*> rowp(k);
  std::vector<uchar> v(k);
  for (int y = 0; y < rows; ++y) {
    for (int i = 0; i < k; ++i) rowp[i] = imgs[i]->ptr<uchar>(y);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < cols; ++x) {
      for (int i = 0; i < k; ++i) v[i] = rowp[i][x];
      std::nth_element(v.begin(), v.begin() + k / 2, v.end());
      o[x] = v[k / 2];
    }
  }
  return out;
}

// Robust sigma of a difference image: median |d| / 0.6745 over a sparse grid.
double robust_noise(const cv::Mat& diff) {
  std::vector<uchar> s;
  s.reserve(diff.total() / 40 + 16);
  for (int y = 3; y < diff.rows; y += 7) {
    const uchar* p = diff.ptr<uchar>(y);
    for (int x = (y * 3) % 5; x < diff.cols; x += 5) s.push_back(p[x]);
  }
  if (s.empty()) return 1.0;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  return std::max(0.5, s[s.size() / 2] / 0.6745);
}

void moments_to_candidate(double m0, double mx, double my, double mxx, double mxy, double myy, Candidate& c) {
  c.area_px = m0;
  c.px = {mx / m0, my / m0};
  const double cxx = mxx / m0 - c.px.x * c.px.x, cyy = myy / m0 - c.px.y * c.px.y, cxy = mxy / m0 - c.px.x * c.px.y;
  const double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l1 = tr / 2 + disc, l2 = std::max(tr / 2 - disc, 1e-9);
  c.elongation = std::sqrt(std::max(l1, 1e-9) / l2);
  // major axis direction in (u, v); counter-clockwise on screen means -v
  const double a = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // angle from +u toward +v
  double deg = -rad2deg(a);
  if (deg <= -90) deg += 180;
  if (deg > 90) deg -= 180;
  c.angle_deg = deg;
}

struct Labels {
  cv::Mat labels, stats, centroids;
  int n = 0;
};

// One frame against its background: candidates with coverage-weighted
// centroids. F and B are 8-bit feature images: grey levels (background
// detector, |F - B| counts) or the marker score (saturation where the hue
// matches; only F - B > 0 counts).
FrameCandidates detect_frame(const cv::Mat& F, const cv::Mat& B, const DetectOptions& o, bool marker, cv::Mat& diff,
                             cv::Mat& weak, Labels& lab) {
  FrameCandidates fc;
  if (marker) cv::subtract(F, B, diff);  // saturates at 0
  else cv::absdiff(F, B, diff);
  fc.noise = robust_noise(diff);
  const double floor_t = marker ? 0.5 * o.marker_min_saturation * 255 : o.min_contrast;
  const double T = std::max(floor_t, o.threshold_sigma * fc.noise);
  const double Tw = 0.5 * T;
  cv::threshold(diff, weak, Tw, 255, cv::THRESH_BINARY);
  lab.n = cv::connectedComponentsWithStats(weak, lab.labels, lab.stats, lab.centroids, 8, CV_32S);
  if (lab.n <= 1) return fc;
  // strongest difference inside each component
  std::vector<uchar> maxd(lab.n, 0);
  std::vector<double> sumd(lab.n, 0.0);
  for (int l = 1; l < lab.n; ++l) {
    if (lab.stats.at<int>(l, cv::CC_STAT_AREA) < o.min_area_px) continue;
    const cv::Rect r(lab.stats.at<int>(l, cv::CC_STAT_LEFT), lab.stats.at<int>(l, cv::CC_STAT_TOP),
                     lab.stats.at<int>(l, cv::CC_STAT_WIDTH), lab.stats.at<int>(l, cv::CC_STAT_HEIGHT));
    for (int y = r.y; y < r.y + r.height; ++y) {
      const int* L = lab.labels.ptr<int>(y);
      const uchar* D = diff.ptr<uchar>(y);
      for (int x = r.x; x < r.x + r.width; ++x)
        if (L[x] == l) {
          if (D[x] > maxd[l]) maxd[l] = D[x];
          sumd[l] += D[x];
        }
    }
  }
  std::vector<int> keep;
  for (int l = 1; l < lab.n; ++l)
    if (lab.stats.at<int>(l, cv::CC_STAT_AREA) >= o.min_area_px && maxd[l] >= T) keep.push_back(l);
  // strongest first: the sum of the difference over the blob
  std::sort(keep.begin(), keep.end(), [&](int a, int b) { return sumd[a] > sumd[b]; });
  if (static_cast<int>(keep.size()) > o.max_candidates) keep.resize(o.max_candidates);
  const cv::Rect full(0, 0, F.cols, F.rows);
  for (int l : keep) {
    const cv::Rect r0(lab.stats.at<int>(l, cv::CC_STAT_LEFT), lab.stats.at<int>(l, cv::CC_STAT_TOP),
                      lab.stats.at<int>(l, cv::CC_STAT_WIDTH), lab.stats.at<int>(l, cv::CC_STAT_HEIGHT));
    const cv::Rect r = cv::Rect(r0.x - 2, r0.y - 2, r0.width + 4, r0.height + 4) & full;
    cv::Mat inside = (lab.labels(r) == l);  // 255 where in the component
    cv::Mat ring;
    cv::dilate(inside, ring, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    // Which side of the background the object is (a glider may be lighter or
    // darker than what is behind it): the side most strong pixels are on.
    int pos = 0, cnt = 0;
    for (int y = 0; y < r.height; ++y) {
      const uchar* I = F.ptr<uchar>(r.y + y) + r.x;
      const uchar* Bg = B.ptr<uchar>(r.y + y) + r.x;
      const uchar* In = inside.ptr<uchar>(y);
      const uchar* D = diff.ptr<uchar>(r.y + y) + r.x;
      for (int x = 0; x < r.width; ++x)
        if (In[x] && D[x] >= T) pos += I[x] > Bg[x], ++cnt;
    }
    const bool brighter = marker || 2 * pos >= cnt;
    // Coverage of a pixel: alpha = |F - B| / |level - B|, where the level is
    // the object's own grey value, taken from the most contrasted pixel of
    // the blob within 2 px (the part of the object nearby that covers its
    // pixel fully). Not 1 for every interior pixel: under motion blur thin
    // parts (a fin shorter than the blur) never cover a pixel fully, and
    // counting them as 1 pulls the centroid toward them. Not one level for
    // the whole blob: wings seen at a slant are darker than the fuselage.
    // Computed as a max filter of (D << 8 | F) over the blob's pixels.
    cv::Mat key = cv::Mat::zeros(r.size(), CV_16U), keymax;
    for (int y = 0; y < r.height; ++y) {
      const uchar* I = F.ptr<uchar>(r.y + y) + r.x;
      const uchar* Bg = B.ptr<uchar>(r.y + y) + r.x;
      const uchar* In = inside.ptr<uchar>(y);
      const uchar* D = diff.ptr<uchar>(r.y + y) + r.x;
      ushort* K = key.ptr<ushort>(y);
      for (int x = 0; x < r.width; ++x)
        if (In[x] && ((I[x] > Bg[x]) == brighter)) K[x] = static_cast<ushort>((D[x] << 8) | I[x]);
    }
    cv::dilate(key, keymax, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)), cv::Point(-1, -1), 1,
               cv::BORDER_CONSTANT, cv::Scalar(0));
    double m0 = 0, mx = 0, my = 0, mxx = 0, mxy = 0, myy = 0, csum = 0;
    for (int y = 0; y < r.height; ++y) {
      const uchar* Bg = B.ptr<uchar>(r.y + y) + r.x;
      const uchar* Ri = ring.ptr<uchar>(y);
      const uchar* D = diff.ptr<uchar>(r.y + y) + r.x;
      const int* L = lab.labels.ptr<int>(r.y + y) + r.x;
      const ushort* KM = keymax.ptr<ushort>(y);
      for (int x = 0; x < r.width; ++x) {
        if (!Ri[x]) continue;
        if (L[x] != l && L[x] != 0) continue;  // another blob
        const double level = KM[x] & 255;
        const double gb = std::abs(level - Bg[x]);
        const double a = KM[x] && gb > Tw ? std::min(1.0, D[x] / gb) : (L[x] == l ? 1.0 : 0.0);
        if (a <= 0) continue;
        const double u = r.x + x, v = r.y + y;
        m0 += a;
        mx += a * u;
        my += a * v;
        mxx += a * u * u;
        mxy += a * u * v;
        myy += a * v * v;
        csum += a * D[x];
      }
    }
    if (m0 <= 0) continue;
    Candidate c;
    moments_to_candidate(m0, mx, my, mxx, mxy, myy, c);
    c.contrast = csum / m0;
    c.x0 = r0.x;
    c.y0 = r0.y;
    c.x1 = r0.x + r0.width - 1;
    c.y1 = r0.y + r0.height - 1;
    c.clipped = c.x0 <= 0 || c.y0 <= 0 || c.x1 >= F.cols - 1 || c.y1 >= F.rows - 1;
    fc.candidates.push_back(c);
  }
  return fc;
}

bool file_exists(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

Detections detect_impl(const std::string& video, const DetectOptions& o);

}  // namespace

Detections detect(const std::string& video, const DetectOptions& o) {
  try {
    return detect_impl(video, o);
  } catch (const cv::Exception& e) {
    throw InputError("cannot read video '" + video + "': OpenCV failed (" + e.err + ")");
  }
}

namespace {
Detections detect_impl(const std::string& video, const DetectOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!file_exists(video)) throw InputError("cannot read video '" + video + "': no such file");
  if (o.chunk_frames < 10) throw InputError("the background chunk must be at least 10 frames");
  if (o.background_samples < 3) throw InputError("the background needs at least 3 sampled frames");
  if (!(o.threshold_sigma > 0) || !(o.min_contrast >= 0)) throw InputError("detection thresholds must be positive");
  if (o.min_area_px < 1 || o.max_candidates < 1) throw InputError("min_area_px and max_candidates must be at least 1");
  if (!(o.fps >= 0) || !std::isfinite(o.fps)) throw InputError("the frame rate must be a positive number");
  for (const auto& [a, b] : o.ranges)
    if (a < 0 || b < a) throw InputError("frame range " + std::to_string(a) + "-" + std::to_string(b) + " is not a valid range");
  cv::VideoCapture cap;
  cap.open(video, cv::CAP_FFMPEG);
  if (!cap.isOpened()) throw InputError("cannot read video '" + video + "': not a video file FFmpeg (through OpenCV) can decode");
  Detections d;
  d.video = video;
  d.detector = o.detector;
  d.width = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_WIDTH));
  d.height = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_HEIGHT));
  const double file_fps = cap.get(cv::CAP_PROP_FPS);
  d.fps = o.fps > 0 ? o.fps : file_fps;
  if (!(d.fps > 0 && d.fps < 10000))
    throw InputError("video '" + video + "' does not state its frame rate: give it (--fps)");
  const int count_hint = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_COUNT));
  // frames to process and frames whose pixels feed the background
  std::vector<FrameRange> ranges = o.ranges;
  std::sort(ranges.begin(), ranges.end());
  const bool all = ranges.empty();
  int last_needed = -1;
  if (!all) {
    for (const auto& r : ranges) last_needed = std::max(last_needed, r.second);
    if (o.detector == Detector::Background) last_needed += o.background_pad;
  }
  auto in_ranges = [&](int f) {
    if (all) return true;
    for (const auto& r : ranges)
      if (f >= r.first && f <= r.second) return true;
    return false;
  };
  auto in_spans = [&](int f) {
    if (all) return true;
    const int pad = o.detector == Detector::Background ? o.background_pad : 0;
    for (const auto& r : ranges)
      if (f >= r.first - pad && f <= r.second + pad) return true;
    return false;
  };
  const int todo = all ? std::max(count_hint, 1) : [&] {
    int n = 0;
    for (const auto& r : ranges) n += r.second - r.first + 1;
    return n;
  }();
  int done = 0;
  const bool marker = o.detector == Detector::Marker;
  // the feature image: grey levels, or the marker score (saturation where the
  // hue is within the tolerance of the marker's and the value is high enough)
  std::function<void(const cv::Mat&, cv::Mat&)> feature;
  if (!marker) {
    feature = [](const cv::Mat& bgr, cv::Mat& out) { cv::cvtColor(bgr, out, cv::COLOR_BGR2GRAY); };
  } else {
    cv::Mat px(1, 1, CV_8UC3, cv::Scalar(o.marker_bgr[0], o.marker_bgr[1], o.marker_bgr[2])), hp;
    cv::cvtColor(px, hp, cv::COLOR_BGR2HSV);
    const int target_h = hp.at<cv::Vec3b>(0, 0)[0];
    if (hp.at<cv::Vec3b>(0, 0)[1] < 80)
      throw InputError("the marker colour is not saturated enough to be told from grey surfaces");
    // weight of a hue: 1 within the tolerance, falling linearly to 0 at twice
    // the tolerance (a soft edge, so that noise near the edge of the band
    // does not switch pixels on and off)
    const double tol = std::max(1.0, o.marker_hue_tolerance_deg / 2);  // OpenCV hue unit: 2 degrees
    cv::Mat lut(1, 256, CV_8U, cv::Scalar(0));
    for (int h = 0; h < 180; ++h) {
      int dh = std::abs(h - target_h);
      dh = std::min(dh, 180 - dh);
      lut.at<uchar>(0, h) = static_cast<uchar>(std::lround(255 * std::clamp(2.0 - dh / tol, 0.0, 1.0)));
    }
    const int vmin = static_cast<int>(std::lround(o.marker_min_value * 255));
    const bool with_grey = o.marker_silhouettes;
    feature = [lut, vmin, with_grey](const cv::Mat& bgr, cv::Mat& out) {
      cv::Mat hsv, ch[3], w, score;
      cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
      cv::split(hsv, ch);
      cv::LUT(ch[0], lut, w);
      cv::multiply(ch[1], w, score, 1.0 / 255);
      score.setTo(0, ch[2] < vmin);
      if (!with_grey) {
        out = score;
        return;
      }
      cv::Mat grey;
      cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
      cv::merge(std::vector<cv::Mat>{score, grey}, out);  // channel 0 marker score, 1 grey
    };
  }
  FrameReader reader(cap, last_needed, feature);
  int idx = -1, last_index = -1;
  cv::Mat img;
  // Sliding buffer of feature images (only frames of the spans: ranges plus
  // their background pad); each chunk of frames gets its own median
  // background from frames sampled over the chunk and its pads.
  std::deque<std::pair<int, cv::Mat>> buf;
  cv::Mat diff, weak;
  Labels lab;
  bool eof = false;
  int last_processed = -1;
  auto pull = [&]() -> bool {
    while (reader.next(idx, img)) {
      last_index = idx;
      if (d.width <= 0) d.width = img.cols, d.height = img.rows;
      if (!in_spans(idx)) continue;
      buf.emplace_back(idx, img);
      return true;
    }
    eof = true;
    return false;
  };
  auto first_to_process = [&]() {
    for (const auto& fr : buf)
      if (fr.first > last_processed && in_ranges(fr.first)) return fr.first;
    return -1;
  };
  while (true) {
    int chunk_start = first_to_process();
    while (chunk_start < 0 && !eof && pull()) chunk_start = first_to_process();
    if (chunk_start < 0) break;
    const int target_end = chunk_start + o.chunk_frames - 1;
    while (!eof && buf.back().first < target_end + o.background_pad) {
      const int before = buf.back().first;
      if (!pull()) break;
      if (buf.back().first != before + 1) break;  // the next span begins: stop at the gap
    }
    // the contiguous block holding chunk_start
    int lo_i = 0;
    while (buf[lo_i].first < chunk_start) ++lo_i;
    int hi_i = lo_i;
    while (hi_i + 1 < static_cast<int>(buf.size()) && buf[hi_i + 1].first == buf[hi_i].first + 1) ++hi_i;
    int blk_lo = lo_i;
    while (blk_lo > 0 && buf[blk_lo - 1].first == buf[blk_lo].first - 1) --blk_lo;
    const int chunk_end = std::min(target_end, buf[hi_i].first);
    std::vector<const cv::Mat*> samples;
    {
      int a = blk_lo, b = hi_i;
      while (a < b && buf[a].first < chunk_start - o.background_pad) ++a;
      while (b > a && buf[b].first > chunk_end + o.background_pad) --b;
      const int n = b - a + 1;
      const int k = std::min(n, o.background_samples);
      for (int s = 0; s < k; ++s) {
        const int j = a + (k == 1 ? 0 : static_cast<int>(std::lround(static_cast<double>(s) * (n - 1) / (k - 1))));
        samples.push_back(&buf[j].second);
      }
    }
    const int nch = samples.front()->channels();
    std::vector<cv::Mat> bgs(nch);
    if (nch == 1) {
      bgs[0] = median_of(samples);
    } else {
      for (int c = 0; c < nch; ++c) {
        std::vector<cv::Mat> chan(samples.size());
        std::vector<const cv::Mat*> ptrs;
        for (std::size_t k = 0; k < samples.size(); ++k) {
          cv::extractChannel(*samples[k], chan[k], c);
          ptrs.push_back(&chan[k]);
        }
        bgs[c] = median_of(ptrs);
      }
    }
    for (int j = lo_i; j <= hi_i && buf[j].first <= chunk_end; ++j) {
      if (!in_ranges(buf[j].first)) continue;
      FrameCandidates fc;
      if (nch == 1) {
        fc = detect_frame(buf[j].second, bgs[0], o, marker, diff, weak, lab);
      } else {
        cv::Mat ch[2];
        cv::split(buf[j].second, ch);
        fc = detect_frame(ch[0], bgs[0], o, true, diff, weak, lab);
        fc.silhouettes = detect_frame(ch[1], bgs[1], o, false, diff, weak, lab).candidates;
      }
      fc.frame = buf[j].first;
      fc.t = fc.frame / d.fps;
      d.frames.push_back(std::move(fc));
      if (o.progress && (++done % 15 == 0)) o.progress(done, todo);
    }
    last_processed = chunk_end;
    const int keep_from = std::max(chunk_end + 1 - o.background_pad, buf[blk_lo].first);
    while (!buf.empty() && buf.front().first < keep_from) buf.pop_front();
  }
  // reading stopped after the last frame needed: the file's count is the video's length
  d.frame_count = all ? last_index + 1 : std::max(last_index + 1, count_hint);
  if (d.frame_count <= 0) throw InputError("cannot read video '" + video + "': it has no frames OpenCV can decode");
  if (d.width <= 0 || d.height <= 0) throw InputError("cannot read video '" + video + "': unknown frame size");
  for (const auto& [a, b] : ranges)
    if (b >= d.frame_count)
      throw InputError("frame range " + std::to_string(a) + "-" + std::to_string(b) + " goes beyond the video's last frame " +
                       std::to_string(d.frame_count - 1));
  if (o.progress) o.progress(todo, todo);
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}
}  // namespace

}  // namespace pteromys::capture
