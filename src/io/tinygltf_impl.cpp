// The one translation unit that compiles tinygltf's implementation (slow to build: nothing else lives here, so
// editing the glTF reader or writer never recompiles it).
//
// The TINYGLTF_* macros come from the project-wide C++ arguments in meson.build, identical for every file that
// includes tiny_gltf.h (a mismatch breaks the link on WriteImageData):
//   TINYGLTF_NO_STB_IMAGE, TINYGLTF_NO_STB_IMAGE_WRITE: images are passed through, never decoded or encoded;
//   TINYGLTF_NO_EXTERNAL_IMAGE: external image files are referenced by URI, not read;
//   TINYGLTF_NO_FS: no default file callbacks (their ExpandFilePath runs wordexp() on URIs from the file);
//     gltf_read.cpp installs its own, which read regular files only.
// TINYGLTF_ENABLE_DRACO is deliberately not defined: tinygltf's Draco path dereferences unchecked bufferView,
// buffer and attribute ids from the file and reports failed decodes as "invalid bufferView". gltf_read.cpp hides
// KHR_draco_mesh_compression from tinygltf and scene.c decodes it with Draco itself after checking every reference.
//
// libdraco carries its own older copy of tinygltf: the library is built with hidden symbol visibility so that
// neither copy binds to the other's symbols.
#include <fstream> // tinygltf 2.7 still writes files with std::ofstream under TINYGLTF_NO_FS (never called here)

#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
