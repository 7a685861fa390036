#include "viewer/request_guard.h"

#include <algorithm>
#include <cctype>

#include "core/message_text.h"
#include "viewer/access_token.h"

namespace ray {

namespace {

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

// The length of the UTF-8 character `text` starts with: 1 to 4, or 0 when it starts with
// none (a stray continuation byte, an overlong form, a surrogate, past U+10FFFF, cut short).
size_t utf8CharacterLength(std::string_view text) {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead < 0x80) return 1;
    size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
    if (lead >= 0xC2 && lead <= 0xDF) length = 2;
    else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        if (lead == 0xE0) low = 0xA0;   // overlong
        if (lead == 0xED) high = 0x9F;  // surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        if (lead == 0xF0) low = 0x90;   // overlong
        if (lead == 0xF4) high = 0x8F;  // past U+10FFFF
    } else return 0;
    if (text.size() < length || byte(1) < low || byte(1) > high) return 0;
    for (size_t i = 2; i < length; ++i)
        if ((byte(i) & 0xC0) != 0x80) return 0;
    return length;
}

GuardVerdict refused(int status, std::string message) { return {status, std::move(message), ""}; }

// The names a browser on this machine reaches a loopback viewer by.
bool namesThisViewer(const std::string& host, int port) {
    const std::string name = lowercase(host);
    for (const char* loopback : {"127.0.0.1", "localhost", "[::1]"})
        if (name == std::string(loopback).append(":").append(std::to_string(port))) return true;
    return false;
}

bool isPage(const RequestFacts& request) { return request.method == "GET" && request.path == kPagePath; }

// The page opened in a frame of a page --frame-ancestors names (a notebook's), the token in
// its URL: the browser enforces the ancestors (the page's Content-Security-Policy), the token
// is checked next.
bool framedWithToken(const RequestFacts& request, const GuardPolicy& policy) {
    const std::string dest = lowercase(request.fetchDest);
    return !policy.frameAncestors.empty() && isPage(request) && request.fetchMode == "navigate" &&
           (dest == "iframe" || dest == "frame") && !request.queryToken.empty();
}

// A request another page made: cross-origin by its Origin, or by Fetch Metadata (which
// browsers send with every request, fetch and form alike). A top-level navigation to the
// page (a link followed, the URL typed) is the user's own and is let through.
std::optional<std::string> crossOriginReason(const RequestFacts& request, const GuardPolicy& policy) {
    if (!request.origin.empty() && request.origin != "http://" + request.host)
        return "it comes from another page (Origin " + quotedForMessage(request.origin) + ")";
    if (framedWithToken(request, policy)) return std::nullopt;
    const std::string site = lowercase(request.fetchSite);
    const bool navigation = isPage(request) && request.fetchMode == "navigate";
    if (!site.empty() && site != "same-origin" && site != "none" && !navigation)
        return "it comes from another page (Sec-Fetch-Site: " + quotedForMessage(site) + ")";
    const std::string dest = lowercase(request.fetchDest);
    if (dest == "iframe" || dest == "frame" || dest == "embed" || dest == "object")
        return "the viewer's page is never shown inside another page";
    return std::nullopt;
}

// The routes that take the token in their query: the page's first visit (the printed URL)
// and the event stream (EventSource sends no headers). Anywhere else a query token would be
// written into logs and histories for nothing: it is not taken.
bool takesQueryToken(const RequestFacts& request) {
    return request.method == "GET" && (request.path == kPagePath || request.path == kEventsPath);
}

// The token the request presents where its route takes one: the query's (takesQueryToken),
// the Authorization header's, and for the page alone the cookie.
std::string presentedToken(const RequestFacts& request, const GuardPolicy& policy) {
    if (takesQueryToken(request) && !request.queryToken.empty()) return request.queryToken;
    if (std::string token = authorizationToken(request.authorization); !token.empty()) return token;
    return isPage(request) ? cookieValue(request.cookie, accessCookieName(policy.port)) : "";
}

// The media type of a Content-Type, parameters and the spaces around it aside (RFC 9110
// allows "application/json ; charset=utf-8"), in any case.
bool saysJson(const std::string& contentType) {
    std::string type = lowercase(contentType.substr(0, contentType.find(';')));
    const size_t first = type.find_first_not_of(" \t"), last = type.find_last_not_of(" \t");
    type = first == std::string::npos ? "" : type.substr(first, last - first + 1);
    return type == "application/json";
}

}  // namespace

GuardVerdict checkRequest(const RequestFacts& request, const GuardPolicy& policy) {
    if (request.method == "OPTIONS")
        return refused(403, "ray view answers no cross-origin requests (no CORS preflight is accepted)");
    if (policy.loopbackOnly && !namesThisViewer(request.host, policy.port))
        return refused(403, "ray view answers only at 127.0.0.1:" + std::to_string(policy.port) + " or localhost:" +
                                std::to_string(policy.port) + ", not at Host " + quotedForMessage(request.host));
    if (std::optional<std::string> reason = crossOriginReason(request, policy))
        return refused(403, "ray view refused the request: " + *reason + "; only its own page may use it");
    if (!policy.token.empty()) {
        if (!tokensMatch(presentedToken(request, policy), policy.token)) {
            if (!request.queryToken.empty() && !takesQueryToken(request))
                return refused(403, "ray view takes the access token in the Authorization header here (Authorization: "
                                    "token <TOKEN>), not in the query: only the page's URL and /events take ?token=");
            return refused(403, "ray view: this viewer needs its access token: open the URL that `ray view` printed "
                                "(with ?token=...), or start it with --no-token");
        }
        if (isPage(request) && !request.queryToken.empty() && !framedWithToken(request, policy))
            return {0, "", accessCookieName(policy.port) + "=" + policy.token + "; Path=/; HttpOnly; SameSite=Strict"};
    }
    if (request.hasBody && !saysJson(request.contentType))
        return refused(415, "ray view takes JSON bodies only: send Content-Type: application/json");
    return {};
}

std::optional<std::string> bodyEncodingProblem(std::string_view body) {
    size_t at = 0;
    while (at < body.size()) {
        const size_t length = utf8CharacterLength(body.substr(at));
        if (length == 0)
            return "the request's body is not UTF-8 text (byte " + std::to_string(at) +
                   " is not part of a UTF-8 character): send JSON encoded in UTF-8";
        at += length;
    }
    return std::nullopt;
}

bool isLoopbackAddress(const std::string& address) {
    return address.rfind("127.", 0) == 0 || address == "::1" || address == "[::1]" || lowercase(address) == "localhost";
}

}  // namespace ray
