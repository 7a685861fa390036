#include "viewer/connection_deadlines.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace ray {

namespace {

using Clock = std::chrono::steady_clock;

// The stream cpp-httplib reads a request from and writes its answer to: the socket, read
// through a buffer, each read ending at the request's deadline as well as after the
// per-read timeout.
class DeadlineStream : public httplib::Stream {
public:
    DeadlineStream(int sock, Clock::duration readTimeout, Clock::duration writeTimeout)
        : sock_(sock), readTimeout_(readTimeout), writeTimeout_(writeTimeout) {}

    void setDeadline(Clock::time_point deadline) {
        deadline_ = deadline;
        outOfTime_ = false;
    }
    bool outOfTime() const { return outOfTime_; }
    // Whether a byte of the next request is there (buffered or on the socket) before the deadline.
    bool awaitData() { return begin_ < end_ || awaitReadable(); }

    bool is_readable() const override { return begin_ < end_ || awaitReadable(); }
    bool is_writable() const override { return awaitWritable(); }

    ssize_t read(char* ptr, size_t size) override {
        if (begin_ == end_) {
            if (!awaitReadable()) return -1;
            const ssize_t got = recv(sock_, buffer_.data(), buffer_.size(), 0);
            if (got <= 0) return got < 0 ? -1 : 0;
            begin_ = 0;
            end_ = size_t(got);
        }
        const size_t n = std::min(size, end_ - begin_);
        std::memcpy(ptr, buffer_.data() + begin_, n);
        begin_ += n;
        return ssize_t(n);
    }

    ssize_t write(const char* ptr, size_t size) override {
        if (!awaitWritable()) return -1;
        return send(sock_, ptr, size, MSG_NOSIGNAL);
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override { address(getpeername, ip, port); }
    void get_local_ip_and_port(std::string& ip, int& port) const override { address(getsockname, ip, port); }
    socket_t socket() const override { return sock_; }

private:
    // Waits for the socket until the per-read timeout or the deadline, whichever comes first.
    bool awaitReadable() const {
        const Clock::time_point now = Clock::now();
        const Clock::duration left = deadline_ - now;
        if (left <= Clock::duration::zero()) {
            outOfTime_ = true;
            return false;
        }
        const bool deadlineFirst = left <= readTimeout_;
        if (poll(POLLIN, std::min(left, readTimeout_))) return true;
        if (deadlineFirst && Clock::now() >= deadline_) outOfTime_ = true;
        return false;
    }

    bool awaitWritable() const { return poll(POLLOUT, writeTimeout_); }

    bool poll(short events, Clock::duration wait) const {
        pollfd fd{sock_, events, 0};
        const auto ms = std::chrono::ceil<std::chrono::milliseconds>(wait).count();
        int ready;
        do ready = ::poll(&fd, 1, int(std::clamp<int64_t>(ms, 0, 60'000)));
        while (ready < 0 && errno == EINTR);
        // A socket shut down (UnprovenConnections) or closed by its client reads as
        // readable: the read that follows sees its end.
        return ready > 0 && (fd.revents & (events | POLLHUP | POLLERR));
    }

    template <typename Ask>
    void address(Ask ask, std::string& ip, int& port) const {
        sockaddr_storage addr{};
        socklen_t length = sizeof addr;
        ip.clear();
        port = 0;
        if (ask(sock_, reinterpret_cast<sockaddr*>(&addr), &length) != 0) return;
        std::array<char, NI_MAXHOST> host{};
        std::array<char, NI_MAXSERV> service{};
        if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), length, host.data(), host.size(), service.data(),
                        service.size(), NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
            ip = host.data();
            port = std::atoi(service.data());
        }
    }

    int sock_;
    Clock::duration readTimeout_, writeTimeout_;
    Clock::time_point deadline_ = Clock::time_point::max();
    mutable bool outOfTime_ = false;
    std::array<char, 4096> buffer_{};
    size_t begin_ = 0, end_ = 0;
};

// The stream of the request this thread is serving (requestOutOfTime).
thread_local const DeadlineStream* currentStream = nullptr;

Clock::duration seconds(time_t sec, time_t usec) { return std::chrono::seconds(sec) + std::chrono::microseconds(usec); }

}  // namespace

uint64_t UnprovenConnections::enter(int sock) {
    std::lock_guard lock(mutex_);
    const uint64_t ticket = next_++;
    entries_.emplace(ticket, Entry{sock});
    size_t waiting = 0;
    for (const auto& [id, entry] : entries_) waiting += !entry.proven && !entry.shutDown;
    if (waiting > bound_) {
        for (auto& [id, entry] : entries_) {
            if (id == ticket || entry.proven || entry.shutDown) continue;
            shutdown(entry.sock, SHUT_RDWR);
            entry.shutDown = true;
            break;
        }
    }
    return ticket;
}

void UnprovenConnections::prove(uint64_t ticket) {
    std::lock_guard lock(mutex_);
    if (auto it = entries_.find(ticket); it != entries_.end()) it->second.proven = true;
}

void UnprovenConnections::leave(uint64_t ticket) {
    std::lock_guard lock(mutex_);
    entries_.erase(ticket);
}

size_t UnprovenConnections::unproven() {
    std::lock_guard lock(mutex_);
    return size_t(std::count_if(entries_.begin(), entries_.end(),
                                [](const auto& entry) { return !entry.second.proven && !entry.second.shutDown; }));
}

bool requestOutOfTime() { return currentStream && currentStream->outOfTime(); }

bool ViewerHttpServer::process_and_close_socket(socket_t sock) {
    const uint64_t ticket = unproven_.enter(sock);
    const bool served = serveConnection(sock, ticket);
    unproven_.leave(ticket);  // before the close: the number may be another socket's after it
    shutdown(sock, SHUT_RDWR);
    close(sock);
    return served;
}

bool ViewerHttpServer::serveConnection(socket_t sock, uint64_t ticket) {
    DeadlineStream stream(sock, seconds(read_timeout_sec_, read_timeout_usec_),
                          seconds(write_timeout_sec_, write_timeout_usec_));
    currentStream = &stream;
    bool served = false, proven = false;
    Clock::duration wait = kHeaderDeadline;  // for the first request's first byte
    for (size_t count = keep_alive_max_count_; count > 0 && svr_sock_ != INVALID_SOCKET; --count) {
        stream.setDeadline(Clock::now() + wait);
        if (!stream.awaitData()) break;
        const Clock::time_point start = Clock::now();
        stream.setDeadline(start + kHeaderDeadline);
        bool closed = false;
        served = process_request(stream, count == 1, closed, [&](httplib::Request& request) {
            stream.setDeadline(start + kBodyDeadline);  // the headers are in: the body's turn
            if (!proven && showsToken_ && showsToken_(request)) {
                proven = true;
                unproven_.prove(ticket);
            }
        });
        if (!served || closed || stream.outOfTime()) break;
        wait = std::chrono::seconds(keep_alive_timeout_sec_);
    }
    currentStream = nullptr;
    return served;
}

}  // namespace ray
