// How long a connection may take over a request, and how many may wait without having shown
// the viewer's token, so that no local process without the token can keep the viewer from
// answering its page.
//
// cpp-httplib gives each connection a server thread for as long as it is open, and its read
// timeout counts from the last byte received: a client that sends one header line every few
// seconds keeps its thread forever, and 30 such clients held every thread while the page's
// requests waited behind them. So the viewer's server (ViewerHttpServer, below) reads each
// connection itself, through a stream whose reads end at deadlines counted from the
// request's start:
//  - a request's headers must have arrived within kHeaderDeadline of its first byte (a new
//    connection: of its accept), its body within kBodyDeadline; a kept-alive connection waits
//    for its next request as long as cpp-httplib's keep-alive timeout. A request out of time
//    is answered 408 (once its request line is in) and its connection closed.
//  - at most kMaxUnproven connections that have not shown the token (UnprovenConnections) are
//    kept: a new one beyond that closes the one that has waited longest. A connection that
//    has shown the token in a request is not counted while it waits for its next one. The
//    page's own requests show the token in their headers, which arrive at once.
#pragma once

#include <httplib.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>

namespace ray {

constexpr auto kHeaderDeadline = std::chrono::seconds(5);
constexpr auto kBodyDeadline = std::chrono::seconds(10);
constexpr size_t kMaxUnproven = 8;

// The connections that have not shown the token yet. Each thread serving a connection
// enters it and leaves it (before closing its socket: a socket is only ever shut down while
// its number is still the connection's).
class UnprovenConnections {
public:
    explicit UnprovenConnections(size_t bound) : bound_(bound) {}

    // Counts `sock` in; when that makes more than the bound, the oldest other one is shut
    // down (its reads end, and its thread closes it). Returns the connection's ticket.
    uint64_t enter(int sock);
    // The connection showed the token: no longer counted.
    void prove(uint64_t ticket);
    void leave(uint64_t ticket);
    size_t unproven();

private:
    struct Entry {
        int sock = -1;
        bool proven = false, shutDown = false;
    };
    std::mutex mutex_;
    std::map<uint64_t, Entry> entries_;  // by ticket: the order they came in
    uint64_t next_ = 0;
    size_t bound_;
};

// Whether the request in hand has run past its deadline (kHeaderDeadline, kBodyDeadline):
// the error handler, on the connection's own thread, answers 408 for it rather than 400.
bool requestOutOfTime();

// cpp-httplib's server with the deadlines and the bound above. `showsToken` says whether a
// request's headers show the token (the guard's verdict); set it before listening.
class ViewerHttpServer : public httplib::Server {
public:
    ViewerHttpServer() : unproven_(kMaxUnproven) {}
    void setShowsToken(std::function<bool(const httplib::Request&)> showsToken) { showsToken_ = std::move(showsToken); }

private:
    // Called by cpp-httplib on a server thread for each accepted connection: serves its
    // requests (keep-alive), then closes it.
    bool process_and_close_socket(socket_t sock) override;
    bool serveConnection(socket_t sock, uint64_t ticket);

    UnprovenConnections unproven_;
    std::function<bool(const httplib::Request&)> showsToken_;
};

}  // namespace ray
