/* The one header bindgen reads. build.rs defines STURMRAY_EMBREE4 when it
 * found Embree 4's header, so the bindings always describe the installed
 * Embree, never a vendored copy. */
#if defined(STURMRAY_EMBREE4)
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif
