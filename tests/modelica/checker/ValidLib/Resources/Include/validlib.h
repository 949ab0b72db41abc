/* The C side of the checker's test package ValidLib (never compiled: the checker reads it). */
#ifndef VALIDLIB_H
#define VALIDLIB_H

#include <stddef.h>

#define VL_API __attribute__((visibility("default")))

typedef void vl_handle;

#ifdef __cplusplus
extern "C" {
#endif

VL_API vl_handle* vl_open(const char* name, double timeout);
VL_API void vl_close(vl_handle* handle);
VL_API int vl_exchange(vl_handle* handle, const double* values, size_t n, int enabled, int unitChoice, int counts[2],
                       double received[3], const char** message);

static inline double scale(double x, double factor) { return x * factor; }

#ifdef __cplusplus
}
#endif

#endif
