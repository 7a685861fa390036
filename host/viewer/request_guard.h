// Who the viewer answers: its own page, and scripts that hold its token; never another web
// page open in the same browser.
//
// Browsers send a site's cookies with requests that any page of the same *site* makes, and
// every port of 127.0.0.1 is one site: a page served on another local port (a dev server, a
// notebook, anything the user browses to that listens on loopback) could post to the viewer
// with the user's cookie attached. So the cookie is only the page's way back in (a reload of
// the bare URL); it opens the page and nothing else. Every other route needs the token
// presented explicitly: in `Authorization: token <TOKEN>` (which a cross-origin page cannot
// send without a CORS preflight, which the viewer refuses) or, for the event stream that
// EventSource opens, in the query. The page gets the token inside itself: served only to
// the token's holder, unreadable by another origin (no CORS headers are ever sent).
//
// Before the token, every request passes the origin checks, with or without --no-token:
//  - Host must name this viewer (127.0.0.1, localhost or [::1] with its port) when it
//    listens on loopback: a DNS-rebound name is refused;
//  - Origin, when sent, must be the viewer's own (http://<Host>);
//  - Sec-Fetch-Site, when sent, must be same-origin or none (the user typed the URL), but
//    for a top-level navigation to the page; the page is never framed (Sec-Fetch-Dest),
//    unless ray view was started with --frame-ancestors and the frame's URL holds the token;
//  - a body (POST) must say it is JSON, which a form cannot;
//  - OPTIONS (a CORS preflight) is refused.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ray {

// What a request shows the guard: its method, path and the headers that matter (empty when
// absent), and the token in its query.
struct RequestFacts {
    std::string method, path;
    std::string host, origin, fetchSite, fetchMode, fetchDest, contentType;
    std::string queryToken, authorization, cookie;
    bool hasBody = false;
};

// What the viewer is: its token (empty with --no-token), its port, and whether it listens on
// loopback only (the Host check).
struct GuardPolicy {
    std::string token;
    int port = 0;
    bool loopbackOnly = true;
    // ray view --frame-ancestors: the pages that may show the viewer's page in a frame (a
    // Content-Security-Policy source list, such as a notebook's origin); empty: none. Such a
    // frame must open the URL with the token in its query (the frame's navigation is
    // cross-site, and a SameSite cookie is not sent there): then the page is served at once.
    std::string frameAncestors = {};
};

struct GuardVerdict {
    int status = 0;             // 0: let it through; else the HTTP status to answer
    std::string message;        // why it was refused, for the answer's body
    std::string setCookie;      // the page's first visit: the cookie to set (then a 303 to /)
};

// The route that serves the page (the one a cookie may open), and the event stream's.
constexpr const char* kPagePath = "/";
constexpr const char* kEventsPath = "/events";

GuardVerdict checkRequest(const RequestFacts& request, const GuardPolicy& policy);

// Why a request's body cannot be JSON text: bytes that are not UTF-8 (RFC 8259 requires it),
// as a sentence naming the first; nullopt when it is UTF-8. The guard runs before the body is
// read: the routes that take a body ask this first (a 400, not a parser's garbled message).
std::optional<std::string> bodyEncodingProblem(std::string_view body);

// Whether listening on `address` (--bind) reaches this machine only: 127.x.x.x, ::1, localhost.
bool isLoopbackAddress(const std::string& address);

}  // namespace ray
