// libsodium's one-time initialisation (thread-safe, idempotent); throws std::runtime_error if it fails.
#pragma once

namespace dhr::secure {
void ensure_sodium();
}
