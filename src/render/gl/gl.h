// OpenGL declarations for the renderer. libOSMesa exports the GL 4.5 core entry
// points directly, so the prototypes from Mesa's headers are enough (no loader).
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
