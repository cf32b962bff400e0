// viewer/src/input/trace_sample.cpp: a trace sample and a trace file's row, each as the
// other (viewer/trial.hpp): what a study records, and what a replay plays.
#include <viewer/trial.hpp>

#include <io/trace_file.hpp>

namespace viewer {

io::TraceRow toTraceRow(const TraceSample& s) {
    io::TraceRow r;
    r.t_s = s.t_s;
    r.head_world = s.head_world;
    r.head_orientation = s.head_orientation;
    r.mode = s.mode == ViewMode::Free ? io::TraceMode::Free : io::TraceMode::Automatic;
    r.scale = s.scale;
    r.hit_world = s.hit_world;
    return r;
}

TraceSample toTraceSample(const io::TraceRow& r) {
    TraceSample s;
    s.t_s = r.t_s;
    s.head_world = r.head_world;
    s.head_orientation = r.head_orientation;
    s.mode = r.mode == io::TraceMode::Free ? ViewMode::Free : ViewMode::Automatic;
    s.scale = r.scale;
    s.hit_world = r.hit_world;
    return s;
}

}  // namespace viewer
