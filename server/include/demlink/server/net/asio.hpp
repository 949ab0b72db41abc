#pragma once
/// Standalone Asio for DEMLink code: include this instead of <asio.hpp>.
///
/// GCC 12 at -O3 reports -Wnull-dereference inside Asio's scheduler after inlining it into
/// our functions (a false positive in code we do not own, and system-header suppression
/// does not reach warnings issued after inlining); the pragma scopes the suppression to
/// Asio's own lines.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <asio.hpp>
#pragma GCC diagnostic pop
