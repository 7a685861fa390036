// runViewer (viewer_server.h): the session, its routes behind the guard, the port bound.
#include "viewer/viewer_server.h"

#include <httplib.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "viewer/connection_deadlines.h"
#include "viewer/request_guard.h"
#include "viewer/viewer_routes.h"
#include "viewer/viewer_session.h"

namespace ray {

namespace {

// Server threads: the routes, the event streams (each holds one while open), the
// connections that have shown the token and at most kMaxUnproven others
// (viewer/connection_deadlines.h).
constexpr size_t kServerThreads = 24;

// SO_REUSEADDR alone: a restarted viewer may take its port back from connections in
// TIME_WAIT, but a port another server listens on stays refused. (cpp-httplib's default
// also sets SO_REUSEPORT, under which two viewers both listened and shared the requests.)
void exclusivePortOptions(socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
}

// Why binding failed, asked again of the system: cpp-httplib only says that it did.
int bindFailure(const std::string& address, int port) {
    addrinfo hints{}, *found = nullptr;
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    if (getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found) return EADDRNOTAVAIL;
    int error = 0;
    int sock = socket(found->ai_family, found->ai_socktype, found->ai_protocol);
    if (sock < 0) error = errno;
    else {
        exclusivePortOptions(sock);
        if (bind(sock, found->ai_addr, found->ai_addrlen) != 0) error = errno;
        close(sock);
    }
    freeaddrinfo(found);
    return error;
}

[[noreturn]] void throwCannotListen(const std::string& address, int port) {
    const int error = bindFailure(address, port);
    const std::string where = address + ":" + std::to_string(port);
    if (error == EADDRINUSE)
        throw AddressInUse("port " + std::to_string(port) + " on " + address +
                           " is already in use (another ray view, or another server); stop it, or choose another "
                           "port: --port N, or --port 0 for any free one");
    throw std::runtime_error("cannot listen on " + where + (error ? std::string(": ") + std::strerror(error) : "") +
                             "; try another --port or --bind");
}

}  // namespace

void runViewer(const ViewerOptions& options, std::unique_ptr<FrameSource> source) {
    Session session(options, std::move(source));
    ViewerHttpServer server;
    server.set_socket_options(exclusivePortOptions);
    server.set_payload_max_length(kMaxRequestBody);
    // A client that stops reading is dropped after this long instead of holding a thread; one
    // that sends slowly, at its request's deadlines (viewer/connection_deadlines.h).
    server.set_write_timeout(5, 0);
    server.set_read_timeout(5, 0);
    server.set_keep_alive_max_count(100);
    // An answer goes out at once: cpp-httplib writes its headers and body apart, and with
    // Nagle's algorithm the body waited for the browser's delayed acknowledgement of the
    // headers on a kept-alive connection, 40 ms or more an answer (a gizmo drag's edits took
    // 120 ms each from the page, 3 ms from a script that opened a connection each time).
    server.set_tcp_nodelay(true);
    server.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
    defineRoutes(server, session, options.token, options.frameAncestors);
    int port = options.port;
    if (port == 0) port = server.bind_to_any_port(options.address);
    else if (!server.bind_to_port(options.address, port)) port = -1;
    if (port < 0) throwCannotListen(options.address, options.port);
    // The cookie's name and the Host check hold the port, known only now (--port 0).
    const GuardPolicy policy{options.token, port, isLoopbackAddress(options.address), options.frameAncestors};
    guardRequests(server, policy);
    server.setShowsToken([policy](const httplib::Request& request) { return passesGuard(request, policy); });
    session.start();
    if (options.onListening) options.onListening(port);
    server.listen_after_bind();
    session.stop();
}

}  // namespace ray
