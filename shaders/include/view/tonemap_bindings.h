// Set-1 bindings of vkgi-view's tone map (shaders/view/tonemap.comp), shared with the viewer
// that dispatches it.
#ifndef VKGI_VIEW_TONEMAP_BINDINGS_H
#define VKGI_VIEW_TONEMAP_BINDINGS_H

#define VIEW_TONEMAP_BINDING_COMPOSITE 0 // linear radiance (RGBA32F composite), read
#define VIEW_TONEMAP_BINDING_TARGET 1    // the swapchain image (RGBA8 UNORM), written

#endif
