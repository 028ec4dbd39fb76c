// Small helpers shared by the benchmark: wall-clock timing with medians, a work-sharing parallel loop (the same
// one drives our BVH and Embree, so neither gets a better scheduler), command-line arguments and CSV output.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include <sched.h>
#include <sys/resource.h>
#include <time.h>

namespace whitted::bench {

/// Seconds since an arbitrary epoch (steady clock).
inline double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU seconds consumed so far by the calling thread.
inline double threadCpuNow() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// CPU seconds (user + system) consumed so far by the whole process, including threads that have ended.
/// Performance note: on a shared machine wall time includes waiting for a core; CPU time does not, so the
/// benchmark reports both.
inline double processCpuNow() {
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/// Median / min / max of a set of timings (seconds).
struct Timing {
  double median = 0.0, min = 0.0, max = 0.0;
  int runs = 0;
};

inline Timing summarize(std::vector<double> t) {
  Timing s;
  if (t.empty()) return s;
  std::sort(t.begin(), t.end());
  std::size_t n = t.size();
  s.median = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
  s.min = t.front();
  s.max = t.back();
  s.runs = int(n);
  return s;
}

/// Runs fn() warmup times untimed, then reps times timed; fn returns the seconds it measured itself (so callers
/// can time only the part that matters) or a negative value to let this function time the whole call.
template <typename Fn>
Timing timeRepeated(int warmup, int reps, Fn&& fn) {
  for (int i = 0; i < warmup; ++i) fn();
  std::vector<double> t;
  for (int i = 0; i < std::max(1, reps); ++i) {
    double t0 = now();
    double own = fn();
    double t1 = now();
    t.push_back(own >= 0.0 ? own : t1 - t0);
  }
  return summarize(std::move(t));
}

/// Like timeRepeated, but settings that are slow get fewer timed runs: the timed run count is cut so the runs
/// take about budgetSeconds (at least one). When the warm-up alone exceeds the budget it is used as the only
/// sample (a multi-second render does not need warming up).
template <typename Fn>
Timing timeBudgeted(int warmup, int reps, double budgetSeconds, Fn&& fn) {
  std::vector<double> t;
  double last = 0.0;
  for (int i = 0; i < warmup; ++i) {
    double t0 = now();
    double own = fn();
    last = own >= 0.0 ? own : now() - t0;
  }
  if (warmup > 0 && last > budgetSeconds) return summarize({last});
  if (warmup > 0 && last > 0.0) reps = std::max(1, std::min(reps, int(budgetSeconds / last)));
  for (int i = 0; i < std::max(1, reps); ++i) {
    double t0 = now();
    double own = fn();
    t.push_back(own >= 0.0 ? own : now() - t0);
  }
  return summarize(std::move(t));
}

/// Splits [0, n) into chunks handed out from an atomic counter to `threads` threads (the calling thread is one of
/// them); fn(begin, end, threadIndex). Returns the wall time in seconds; cpuSeconds (if given) receives the CPU
/// time the workers spent, summed over threads.
/// Performance note: chunks of 256 rays keep the counter off the profile and balance incoherent batches.
template <typename Fn>
double parallelFor(std::size_t n, int threads, Fn&& fn, double* cpuSeconds = nullptr, std::size_t chunk = 256) {
  std::atomic<std::size_t> next{0};
  std::vector<double> cpu(std::size_t(std::max(1, threads)), 0.0);
  auto worker = [&](int index) {
    double c0 = threadCpuNow();
    for (;;) {
      std::size_t b = next.fetch_add(chunk);
      if (b >= n) break;
      fn(b, std::min(n, b + chunk), index);
    }
    cpu[std::size_t(index)] = threadCpuNow() - c0;
  };
  double t0 = now();
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& th : pool) th.join();
  double wall = now() - t0;
  if (cpuSeconds) {
    *cpuSeconds = 0.0;
    for (double c : cpu) *cpuSeconds += c;
  }
  return wall;
}

/// Restricts the calling thread, and every thread it starts while the object lives, to the first n CPUs it may
/// run on (Linux affinity; threads inherit their creator's mask); restores the mask on destruction. The
/// benchmark uses it to run code that picks its own thread count (our BVH builder) on n cores, for comparisons
/// at equal thread counts. n <= 0 or n >= the usable CPUs: no change.
class CpuLimit {
 public:
  explicit CpuLimit(int n) {
    CPU_ZERO(&saved_);
    if (n <= 0 || sched_getaffinity(0, sizeof saved_, &saved_) != 0 || n >= CPU_COUNT(&saved_)) return;
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int c = 0, k = 0; c < CPU_SETSIZE && k < n; ++c)
      if (CPU_ISSET(c, &saved_)) {
        CPU_SET(c, &set);
        ++k;
      }
    active_ = sched_setaffinity(0, sizeof set, &set) == 0;
  }
  ~CpuLimit() {
    if (active_) sched_setaffinity(0, sizeof saved_, &saved_);
  }
  CpuLimit(const CpuLimit&) = delete;
  CpuLimit& operator=(const CpuLimit&) = delete;

 private:
  cpu_set_t saved_;
  bool active_ = false;
};

/// "--key value" and "--flag" arguments after the sub-command.
class Args {
 public:
  Args(int argc, char** argv, int first) {
    for (int i = first; i < argc; ++i) {
      std::string a = argv[i];
      if (a.rfind("--", 0) != 0) {
        positional_.push_back(a);
        continue;
      }
      a = a.substr(2);
      if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) {
        values_[a] = argv[++i];
      } else {
        values_[a] = "";
      }
    }
  }
  bool has(const std::string& k) const { return values_.count(k) != 0; }
  std::string str(const std::string& k, const std::string& def = "") const {
    auto it = values_.find(k);
    return it == values_.end() ? def : it->second;
  }
  int integer(const std::string& k, int def) const { return has(k) ? std::atoi(str(k).c_str()) : def; }
  double real(const std::string& k, double def) const { return has(k) ? std::atof(str(k).c_str()) : def; }
  /// "WxH" sizes.
  bool size(const std::string& k, int& w, int& h) const {
    if (!has(k)) return false;
    return std::sscanf(str(k).c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0;
  }
  /// Comma-separated list.
  std::vector<std::string> list(const std::string& k, const std::string& def) const {
    std::vector<std::string> out;
    std::string s = str(k, def), cur;
    for (char c : s) {
      if (c == ',') {
        if (!cur.empty()) out.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
  }

 private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

/// Appends rows to a CSV file, writing the header only when the file is new or empty.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& header) {
    if (path.empty()) return;
    FILE* probe = std::fopen(path.c_str(), "rb");
    bool fresh = true;
    if (probe) {
      fresh = std::fgetc(probe) == EOF;
      std::fclose(probe);
    }
    f_ = std::fopen(path.c_str(), "ab");
    if (f_ && fresh) row(header);
  }
  ~CsvWriter() {
    if (f_) std::fclose(f_);
  }
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  bool ok() const { return f_ != nullptr; }
  void row(const std::vector<std::string>& cells) {
    if (!f_) return;
    for (std::size_t i = 0; i < cells.size(); ++i) std::fprintf(f_, "%s%s", i ? "," : "", cells[i].c_str());
    std::fprintf(f_, "\n");
    std::fflush(f_);
  }

 private:
  FILE* f_ = nullptr;
};

/// Number formatting for CSV cells.
inline std::string fmt(double v, const char* f = "%.6g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
template <typename T, typename = std::enable_if_t<std::is_integral_v<T>>>
std::string fmt(T v) {
  return std::to_string(v);
}

}  // namespace whitted::bench
