# third_party/dependencies.cmake: every library the build finds, once, with the
# minimum version accepted (the Debian 13 version the project is tested with).
# Modules link the imported targets; none of them calls find_package itself.
# The Debian package that provides each one is listed in packages-build.txt.

find_package(Threads REQUIRED)
find_package(glm 0.9.9 REQUIRED)                         # libglm-dev
find_package(nlohmann_json 3.11 REQUIRED)                # nlohmann-json3-dev

find_package(assimp 5.4 REQUIRED)                        # libassimp-dev
find_path(LADARVR_STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb REQUIRED)  # libstb-dev
find_library(LADARVR_STB_LIBRARY NAMES stb REQUIRED)
find_path(LADARVR_LZF_INCLUDE_DIR lzf.h PATH_SUFFIXES liblzf lzf REQUIRED)  # liblzf-dev
find_library(LADARVR_LZF_LIBRARY NAMES lzf REQUIRED)
# LASzip ships neither a CMake package nor a .pc file: the header, the API library and
# the version from laszip_api_version.h (3.4 has the stream reader and writer we use;
# they are in liblaszip, not in liblaszip_api).
find_path(LADARVR_LASZIP_INCLUDE_DIR laszip/laszip_api.h REQUIRED)  # liblaszip-dev
find_library(LADARVR_LASZIP_LIB NAMES laszip REQUIRED)  # the stream API lives here
file(STRINGS ${LADARVR_LASZIP_INCLUDE_DIR}/laszip/laszip_api_version.h LADARVR_LASZIP_VERSION_LINES
     REGEX "#define LASZIP_API_VERSION_(MAJOR|MINOR|PATCH) ")
string(REGEX REPLACE ".*MAJOR ([0-9]+).*MINOR ([0-9]+).*PATCH ([0-9]+).*" "\\1.\\2.\\3"
       LADARVR_LASZIP_VERSION "${LADARVR_LASZIP_VERSION_LINES}")
if(LADARVR_LASZIP_VERSION VERSION_LESS 3.4)
  message(FATAL_ERROR "LASzip ${LADARVR_LASZIP_VERSION} found; ladarvr needs 3.4 or newer (liblaszip-dev)")
endif()

# platform's SHA-256, in the fuzz build too.
find_package(OpenSSL 3.0 REQUIRED COMPONENTS Crypto)    # libssl-dev

if(LADARVR_FUZZ)
  return()  # the fuzz build compiles the parsers of core and io only
endif()

find_package(embree 4.3 REQUIRED)                        # libembree-dev
find_package(TBB 2021.5 REQUIRED COMPONENTS tbb)         # libtbb-dev
find_package(PCL 1.14 REQUIRED COMPONENTS common io segmentation sample_consensus)  # libpcl-dev
list(REMOVE_ITEM PCL_INCLUDE_DIRS /usr/include)  # as -isystem it breaks <cmath>'s include_next
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL GLX)  # libgl-dev, libegl-dev
find_package(glfw3 3.4 REQUIRED)                         # libglfw3-dev
find_package(OpenXR 1.1 REQUIRED)                        # libopenxr-dev
find_package(X11 REQUIRED)                               # libx11-dev
find_package(CLI11 2.4 REQUIRED)                         # libcli11-dev
if(LADARVR_BUILD_TESTS)
  find_package(doctest 2.4.11 REQUIRED)                  # doctest-dev
endif()

# Tools run at build time.
find_program(LADARVR_GLSLANG_VALIDATOR glslangValidator REQUIRED)  # glslang-tools
find_program(LADARVR_GLAD_EXECUTABLE glad)                         # python3-glad
if(NOT LADARVR_GLAD_EXECUTABLE)
  find_package(Python3 REQUIRED COMPONENTS Interpreter)
endif()

# Libraries that ship headers (and a .so) but no CMake package.
find_path(LADARVR_IMGUI_INCLUDE_DIR imgui.h PATH_SUFFIXES imgui REQUIRED)   # libimgui-dev
find_library(LADARVR_IMGUI_LIBRARY NAMES imgui REQUIRED)
find_path(LADARVR_XGBOOST_INCLUDE_DIR xgboost/c_api.h REQUIRED)  # libxgboost-dev (3.0), under /usr/include
find_library(LADARVR_XGBOOST_LIBRARY NAMES xgboost REQUIRED)

# Shares compiled objects between clones, worktrees and presets when ccache is there.
# Paths under the checkout are hashed relative to it (CCACHE_BASEDIR), and the build
# folder is left out of the hash of objects with debug information (CCACHE_NOHASHDIR),
# so the asan preset's objects are shared between clones too; their debug information
# then names the folder of the clone that compiled them first. The checkout's own path is
# compiled into three objects only (tests/common/test_paths.cpp, io's scene_file.cpp,
# bench's common.cpp): every other object one clone compiled, the next finds in the cache.
find_program(LADARVR_CCACHE ccache)
if(LADARVR_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(LADARVR_CCACHE_ENV CCACHE_BASEDIR=${CMAKE_SOURCE_DIR} CCACHE_NOHASHDIR=true)
  set(CMAKE_C_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env ${LADARVR_CCACHE_ENV} ${LADARVR_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env ${LADARVR_CCACHE_ENV} ${LADARVR_CCACHE})
endif()
