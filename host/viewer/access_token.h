// Who may use the viewer: whoever holds the random token printed in its URL (as Jupyter
// does), so that on a shared machine another local user cannot drive it, read the scene's
// explanations or save its images. The page's first visit carries the token in the query
// (?token=...); the server answers with a cookie holding it and sends the browser on to the
// bare URL, so the token leaves the address bar and the history. Scripts send it as
// `Authorization: token <TOKEN>`. Which route takes which (the cookie opens the page alone)
// is viewer/request_guard.h's.
#pragma once

#include <string>

namespace ray {

// 32 hex digits (128 bits) from the system's random source (getrandom).
std::string newAccessToken();

// The cookie that carries the token: one per port, so that two viewers on one host do not
// overwrite each other's (cookies are kept per host, not per port).
std::string accessCookieName(int port);

// The token of an `Authorization: token <TOKEN>` header (the scheme in any case); empty
// when the header is another or absent.
std::string authorizationToken(const std::string& header);

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or empty.
std::string cookieValue(const std::string& header, const std::string& name);

// Compares in time independent of where the strings differ.
bool tokensMatch(const std::string& presented, const std::string& expected);

}  // namespace ray
