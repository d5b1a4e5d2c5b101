// toml++'s implementation, compiled once: the native build links Debian's compiled library, the
// WebAssembly build uses the header-only package's sources (web/wasm_dependencies.cmake).
#define TOML_HEADER_ONLY 0
#define TOML_IMPLEMENTATION
#include <toml++/toml.h>
