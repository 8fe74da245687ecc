/* polarcam/export.h - PC_API marks the public API.
 *
 * libpolarcam is built with hidden symbol visibility: a function is part of the shared
 * library's interface only when an installed header declares it with PC_API. Everything else
 * (helpers shared between the library's own files) stays internal, so that it can change
 * without breaking programs linked against the library. Static linking is unaffected.
 */
#ifndef POLARCAM_EXPORT_H
#define POLARCAM_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define PC_API __attribute__((visibility("default")))
#else
#define PC_API
#endif

#endif
