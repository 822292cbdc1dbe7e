// The one translation unit that compiles tinygltf (Debian's header). Its configuration
// macros (Draco on, no image writing) are target compile definitions in CMakeLists.txt,
// so every file that includes tiny_gltf.h sees the same declarations.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
