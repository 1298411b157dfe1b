/// @file export.h
/// Symbol visibility of the public API.
///
/// The library is compiled with hidden visibility by default (`-fvisibility=hidden`);
/// every declaration of the public API in include/elastopt/ carries `EO_API`, so only
/// those symbols are exported from libelastopt.so. Internal functions shared between the
/// library's own files stay hidden (they are still linkable from the static library,
/// which the in-tree tests use).
///
/// ```c
/// EO_API int eo_sim_step(eo_sim *s, eo_sim_step_result *r);
/// ```
#ifndef ELASTOPT_EXPORT_H
#define ELASTOPT_EXPORT_H

#if defined(EO_BUILDING_LIBRARY) && (defined(__GNUC__) || defined(__clang__))
#define EO_API __attribute__((visibility("default")))
#else
#define EO_API
#endif

#endif
