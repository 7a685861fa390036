// The viewer's HTTP face: every request through the guard (viewer/request_guard.h) first,
// then its route, which asks the session (viewer/viewer_session.h) and answers JSON; every
// refusal says why, in a JSON "error".
#pragma once

#include <cstddef>
#include <string>

namespace httplib {
class Server;
struct Request;
}

namespace ray {

class Session;
struct GuardPolicy;

// Request bodies over this many bytes are refused (413): the largest request, a view with
// every setting, is well under 1 KiB.
constexpr size_t kMaxRequestBody = 16 * 1024;

// The routes of viewer_server.h, answered by `session`; `token` is written into the page
// (empty with --no-token: the editing routes then answer 403).
// frameAncestors: ray view --frame-ancestors (GuardPolicy), written into the page's policy.
void defineRoutes(httplib::Server& server, Session& session, const std::string& token,
                  const std::string& frameAncestors);

// The guard before every route, the protective headers on every answer, and a JSON error
// for the refusals cpp-httplib makes itself.
void guardRequests(httplib::Server& server, const GuardPolicy& policy);

// Whether the guard lets `request` through (its headers show the token, where one is needed).
bool passesGuard(const httplib::Request& request, const GuardPolicy& policy);

}  // namespace ray
