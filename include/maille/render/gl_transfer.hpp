// Device positions across two OpenGL contexts of one share group (the viewer's physics thread
// and its window): a copy on the GPU into the exchange slot's buffer, fenced both ways with sync
// objects (glFenceSync / glWaitSync), so neither thread blocks on the other's GPU work.
#pragma once

#include <memory>

#include "maille/render/snapshot_exchange.hpp"

namespace maille::render {

std::unique_ptr<DeviceTransfer> make_gl_transfer();

}  // namespace maille::render
