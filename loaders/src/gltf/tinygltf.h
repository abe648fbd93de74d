// tinygltf (Debian's libtinygltf-dev), configured the one way softpbr uses it: JSON through
// nlohmann-json, no image decoding (images are decoded by softpbr::image, with its
// limits), no reading of external image files (the loader reads the ones its materials
// use, in parallel, straight into the buffers it decodes from: gltf/files.h), no image
// writing. Included by the glTF reader's files and by tinygltf.cpp, the one translation
// unit that compiles its implementation.
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
