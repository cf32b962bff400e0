#!/usr/bin/env bash
# engine_rewrite.sh: rewrites code written against the former `engine` module (a branch
# older than the split) to the
# core / io / platform modules: include paths, namespace qualifiers (engine::X ->
# core::X, io::X or platform::X by symbol), file paths named in comments and docs, and
# CMake link lines (`engine` -> `core io platform`).
#
# Usage:  scripts/engine_rewrite.sh [CHECKOUT]     (default: the current directory)
# Idempotent: a second run changes nothing. It touches tracked and untracked (not ignored)
# files only, never build/ or third_party/. At the end it lists any `engine::` or
# `engine/` reference it did not know how to rewrite (fix those by hand).
set -euo pipefail
root="${1:-.}"
cd "$root"
git rev-parse --is-inside-work-tree >/dev/null

mapfile -t files < <(git ls-files -co --exclude-standard |
  grep -Ev '^(build|third_party)/|^scripts/engine_rewrite\.sh$' |
  grep -E '(\.(cpp|hpp|h|cc|md|txt|cmake|py|sh|json|glsl|vert|frag|comp)$|^ladarvr$|CMakeLists\.txt$)' || true)

# The project's modules (folders with include/<module>/): a run of their includes is
# kept sorted after the rewrite (core/, io/ and platform/ no longer sort where engine/ did).
modules=$( (ls -d */include/*/ 2>/dev/null; echo core/ io/ platform/ | tr ' ' '\n') | cut -d/ -f1 | sort -u | paste -sd'|')
export LADARVR_MODULES="$modules"

perl -0777 -i -pe '
  BEGIN {
    %ns = ();
    $ns{$_} = "core" for qw(Error shownNumber printable Pose Bounds kMaxWorldCoordinate_m
      kMaxLocalCoordinate_m Role kRoleCount roleName parseRole RoleMask Mesh Scene CloudPoint
      CloudFields PointCloud packRgb kWhite MeshSummary TargetSummary SceneSummary summarize
      groundHeightAt kMaxTargetSize_m kMaxTargetGroundGap_m targetWarnings Candidate jetTable
      jetIndex CellKey cellOf CellKeyHash CellBins binByCell multiply64 uniformBelow shuffle
      SplitMix64 mix64 SceneEntry kDefaultReflectance);
    $ns{$_} = "io" for qw(CloudFormat parseCloudFormat formatForPath cloudFormatName LasOptions
      lazChunkPoints lazChunkBytes CloudWriter writeCloud readCloud readCloudData CloudReader
      PngRows encodePng writePng parseStrictJson jsonTypeName SceneLoadOptions kMaxSceneBytes
      loadScene loadSceneJson demoScenePath readCandidates writeCandidates
      TraceMode traceModeName TraceRow Trace kTraceHeader kMaxTraceBytes formatTraceRow
      parseTrace readTrace forEachTraceRow kTraceBlockBytes kMaxTraceLineBytes kMaxJsonDepth
      loadMeshVertices);
    $ns{$_} = "platform" for qw(kTempPrefix regularFileProblem checkInputFile readTextFile
      checkNotAnInput TempFile openScratchFile removeStaleTemporaries OwnedName
      checkOutputFolder writeFolderAtomic AtomicFolder writeFileAtomic
      checkWritableDestination removeTemporariesNow Watchdog Progress kMaxPathBytes kMaxNameBytes
      checkPathLength PathRole RunPath checkDistinctPaths removeOwnFolder openOwnFile readOwnFile
      makeOwnFolder rememberInputFolder);
    %detail = ();
    $detail{$_} = "platform" for qw(registerTemporary unregisterTemporary);
    $detail{$_} = "io" for qw(LasRecord LasInventory LasSink ByteSource FormatReader
      lazChunkTable openLasSink openLazSink);
    # Public headers: old name -> new name (scene.hpp and candidates.hpp are decided per file).
    %hdr = (error => "core/error.hpp", frames => "core/frames.hpp",
      point_cloud => "core/point_cloud.hpp", scene_info => "core/scene_info.hpp",
      jet => "core/jet.hpp", spatial_hash => "core/spatial_hash.hpp",
      shuffle => "core/random.hpp", cloud_io => "io/cloud_io.hpp",
      cloud_reader => "io/cloud_reader.hpp", png => "io/png.hpp",
      strict_json => "io/strict_json.hpp", trace_file => "io/trace_file.hpp", safe_file => "platform/safe_file.hpp",
      atomic_file => "platform/atomic_file.hpp", cleanup => "platform/cleanup.hpp",
      progress => "platform/progress.hpp");
    # Sources named in comments and docs.
    %src = (map({ $_ => "core/src/$_" } qw(point_cloud.cpp scene_info.cpp jet.cpp spatial_hash.cpp)),
      "scene.cpp" => "io/src/scene_file.cpp", "candidates.cpp" => "io/src/candidates_file.cpp",
      "cloud_io.cpp" => "io/src/cloud_writer.cpp",
      map({ $_ => "io/src/$_" } qw(cloud_reader.cpp cloud_decode.cpp cloud_decode.hpp png.cpp strict_json.cpp
        trace_file.cpp)),
      "pcd_reader.cpp" => "io/src/pcd/pcd_reader.cpp", "ply_reader.cpp" => "io/src/ply/ply_reader.cpp",
      map({ $_ => "io/src/las/$_" } qw(las_reader.cpp las_writer.cpp las_record.cpp las_record.hpp
        las_sink.hpp laz_writer.cpp laz_chunk_table.cpp laz_chunk_table.hpp)),
      map({ $_ => "platform/src/$_" } qw(safe_file.cpp atomic_file.cpp cleanup.cpp progress.cpp)),
      "text.hpp" => "core/include/core/error.hpp");
    %tst = (map({ $_ => "tests/core/$_" } qw(jet_test.cpp spatial_hash_test.cpp scene_info_test.cpp)),
      "shuffle_test.cpp" => "tests/core/random_test.cpp",
      "scene_test.cpp" => "tests/io/scene_file_test.cpp",
      "candidates_test.cpp" => "tests/io/candidates_file_test.cpp",
      map({ $_ => "tests/io/$_" } qw(cloud_io_test.cpp cloud_reader_test.cpp las_io_test.cpp
        laz_writer_test.cpp pcd_readback_test.cpp png_test.cpp fuzz_regression_test.cpp
        cloud_tool.cpp las_interop_test.py assets_test.cpp trace_file_test.cpp)),
      map({ $_ => "tests/platform/$_" } qw(atomic_file_test.cpp progress_test.cpp)));
  }
  my $file = $ARGV;
  if ($file =~ /CMakeLists\.txt$|\.cmake$/) {
    s/^(\s*)add_subdirectory\(engine\)/$1add_subdirectory(core)\n$1add_subdirectory(platform)\n$1add_subdirectory(io)/mg;
    s{(target_link_libraries\s*\(\s*[^\s)]+)([^)]*\))}{ my ($h, $t) = ($1, $2); $t =~ s/(?<![\w\$\{:\/.-])engine(?![\w.\/-])/core io platform/g; $h . $t }ge;
  }
  my $wants_scene_file = /\b(loadScene|loadSceneJson|demoScenePath|SceneLoadOptions|kMaxSceneBytes)\b/;
  my $wants_candidates_file = /\b(readCandidates|writeCandidates)\b/;
  # Full paths first (docs and comments), then include-style paths.
  s{\bengine/include/engine/scene\.hpp}{$wants_scene_file ? "io/include/io/scene_file.hpp" : "core/include/core/scene.hpp"}ge;
  s{\bengine/include/engine/candidates\.hpp}{$wants_candidates_file ? "io/include/io/candidates_file.hpp" : "core/include/core/candidates.hpp"}ge;
  s{\bengine/include/engine/(\w+)\.hpp}{ exists $hdr{$1} ? do { my $h = $hdr{$1}; my ($m) = $h =~ m{^(\w+)/}; "$m/include/$h" } : $& }ge;
  s{\bengine/src/([\w.]+\.(?:cpp|hpp))}{ exists $src{$1} ? $src{$1} : $& }ge;
  s{\btests/engine/([\w.]+\.(?:cpp|py))}{ exists $tst{$1} ? $tst{$1} : $& }ge;
  s{\btests/engine\b(?!/)}{tests/io}g;
  s{(?<![\w/])engine/scene\.hpp}{$wants_scene_file ? "io/scene_file.hpp" : "core/scene.hpp"}ge;
  s{(?<![\w/])engine/candidates\.hpp}{$wants_candidates_file ? "io/candidates_file.hpp" : "core/candidates.hpp"}ge;
  s{(?<![\w/])engine/(\w+)\.hpp}{ exists $hdr{$1} ? $hdr{$1} : $& }ge;
  # The split headers: a file that names what moved out of a header it (or a header it
  # includes) used to get gets the new header. Inserted into its run of module includes.
  for my $need (["platform/output_folder.hpp", qr/\bplatform::(?:OwnedName|checkOutputFolder|writeFolderAtomic|AtomicFolder)\b/],
                ["io/candidates_file.hpp", qr/\bio::(?:readCandidates|writeCandidates)\b/],
                ["io/scene_file.hpp", qr/\bio::(?:loadScene|loadSceneJson|demoScenePath|SceneLoadOptions|kMaxSceneBytes)\b/]) {
    my ($h, $re) = @$need;
    next unless $file =~ /\.(cpp|hpp|h|cc)$/ && $file !~ m{^(core|io|platform)/};
    next unless /$re/ && !/#include <\Q$h\E>/;
    s{^(#include <(?:core|io|platform)/[^>]*>\n)}{#include <$h>\n$1}m
      or s{^(#include <[^>]*>\n)\n}{$1\n#include <$h>\n\n}m
      or s{^(#include "[^"]*"\n)}{$1#include <$h>\n}m;
  }
  # The test data of the old engine tests: tests/data/engine -> tests/data/io.
  s{\btests/data/engine\b}{tests/data/io}g;
  s{(LADARVR_TEST_DATA_DIR\)\s*/\s*|\bkData\s*/\s*)"engine"}{$1"io"}g if $file =~ m{^(tests|fuzz)/};
  # ctest names: engine.X became core.X, io.X or platform.X.
  if ($file =~ m{(^|/)mutants\.txt$}) { s{\^engine\\\.}{^(core|io|platform)\\.}g; s{\(engine\|}{(core|io|platform|}g; }
  # ctest entries named in docs and lists: engine.<test> became core., io. or platform.<test>.
  s{\bengine\.(?=(?:jet|spatial hash|shuffle|random|targetWarnings|summarize|groundHeightAt|shownNumber)\b)}{core.}g;
  s{\bengine\.(?=(?:atomic_file|progress|output_folder)\b)}{platform.}g;
  s{\bengine\.(?=(?:scene|cloud_io|cloud_reader|las_io|las_interop|png|laz_writer|fuzz regression|candidates|trace_file|pcl|assets|every kept|PCL\x27s count|shown bytes)\b)}{io.}g;
  # Keep each run of module includes sorted (only runs that hold core/, io/ or platform/).
  my $mods = $ENV{LADARVR_MODULES};
  s{((?:^#include <(?:$mods)/[^>]*>\n)+)}{ my $r = $1; $r =~ m{<(?:core|io|platform)/} ? join("", sort split(/(?<=\n)/, $r)) : $r }gme;
  s{\bengine::detail::(\w+)}{ exists $detail{$1} ? "$detail{$1}::detail::$1" : $& }ge;
  s{\bengine::(\w+)}{ exists $ns{$1} ? "$ns{$1}::$1" : $& }ge;
' "${files[@]}"

# What is left: references the maps above do not know.
left=$(git ls-files -co --exclude-standard | grep -Ev '^(build|third_party)/|^scripts/engine_rewrite\.sh$' |
  xargs grep -nE '\bnamespace engine\b|\bengine::|[<"]engine/|\bengine/(include|src)/|tests/engine/' 2>/dev/null || true)
if [ -n "$left" ]; then
  echo "engine-rewrite: references left to fix by hand:" >&2
  echo "$left" >&2
fi
