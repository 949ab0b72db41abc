/* Loads a shared library the way an FMI master or a Modelica tool does (dlopen), calls one
 * of its `const char* f(void)` functions (dl_version, fmi2GetVersion) and fails when the
 * process then maps any C++ runtime or protobuf library: proof that the library runs on a
 * machine without them. Linked with nothing but libc.
 * Usage: load_library LIBRARY FUNCTION. Prints "FUNCTION() = VALUE"; exit 0, else 1. */
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

static const char* const kForbidden[] = {"libstdc++", "libprotobuf", "libgcc_s", "libabsl"};

int main(int argc, char** argv) {
  void* library;
  const char* (*function)(void);
  const char* value;
  char line[4096];
  FILE* maps;
  int bad = 0;
  size_t i;
  if (argc != 3) {
    fprintf(stderr, "usage: %s LIBRARY FUNCTION\n", argv[0]);
    return 2;
  }
  library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (library == NULL) {
    fprintf(stderr, "load_library: dlopen: %s\n", dlerror());
    return 1;
  }
  *(void**)(&function) = dlsym(library, argv[2]);
  if (function == NULL) {
    fprintf(stderr, "load_library: %s is not exported\n", argv[2]);
    return 1;
  }
  value = function();
  printf("%s() = %s\n", argv[2], value != NULL ? value : "(null)");
  maps = fopen("/proc/self/maps", "r");
  if (maps == NULL) {
    fprintf(stderr, "load_library: cannot read /proc/self/maps\n");
    return 1;
  }
  while (fgets(line, sizeof line, maps) != NULL) {
    for (i = 0; i < sizeof kForbidden / sizeof kForbidden[0]; ++i) {
      if (strstr(line, kForbidden[i]) != NULL) {
        fprintf(stderr, "load_library: the process mapped %s", strchr(line, '/') != NULL ? strchr(line, '/') : line);
        bad = 1;
      }
    }
  }
  fclose(maps);
  return bad || value == NULL || value[0] == '\0' ? 1 : 0;
}
