// The implementation of tinygltf, compiled once (see tinygltf.h).
#define TINYGLTF_IMPLEMENTATION
#include "gltf/tinygltf.h"
