// SPDX-License-Identifier: MIT
#pragma once
// The files one tool run writes, made whole or not at all (docs/tools.md, "Outputs").
//
//   fabsynth::tool::output_set outputs;
//   const auto stl = outputs.add(dir / "solid.stl");      // right after the options are checked
//   const auto report = outputs.add_manifest(dir / "report.json");
//   ... the work ...
//   io::write_stl(stl, mesh);                            // writes the staged file, not dir/solid.stl
//   outputs.commit();                                    // every file moves into place at once
//
// Every file is first written into a hidden staging directory `.fabsynth-stage-<pid>` next to its
// final place (in the nearest directory that exists, so that moving it is a rename within one file
// system) and is moved into place only by commit(), after all work succeeded. Until then no final
// path is touched: a failed, refused or interrupted run leaves the previous outputs as they were
// and creates no output directory. commit() blocks SIGINT, SIGTERM and SIGHUP while it renames, so
// those signals cannot split a set; it first removes the previous manifests and moves the new ones
// last, so a reader that trusts a manifest never sees a mixed set, even after SIGKILL or a power
// loss mid-commit. SIGINT, SIGTERM and SIGHUP during the work remove the staging directory (with
// system calls only, from the handler); one left by SIGKILL is removed by the next run that stages
// in the same directory. Linux-specific (getdents64), as the project's platform is.
//
// Staging early also checks, before any work, that every output directory can be written.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <list>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <fabsynth/core/error.hpp>

namespace fabsynth::tool {

namespace detail {

// What the signal handler removes: the staging directories, as C strings allocated before the
// handler can run. One output_set per process is the supported case (a tool run).
struct staging_registry {
    static constexpr int max_dirs = 64;
    const char* dirs[max_dirs];
    std::atomic<int> count{0};
    std::atomic<bool> in_use{false};
    std::atomic<bool> committing{false};  // a signal then waits for the end of commit()
    std::atomic<int> pending{0};
};
inline staging_registry& registry() {
    static staging_registry r;
    return r;
}

// Removes a staging directory and the files in it with system calls only (open, getdents64,
// unlinkat, rmdir are async-signal-safe; opendir and std::filesystem allocate). Retried because a
// worker thread may still create a file while the handler runs.
inline void remove_staging_directory(const char* dir) noexcept {
    struct dirent64_record {
        std::uint64_t ino;
        std::int64_t off;
        unsigned short reclen;
        unsigned char type;
        char name[1];
    };
    for (int pass = 0; pass < 8; ++pass) {
        const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (fd < 0) return;
        alignas(8) char buf[4096];
        for (long n; (n = ::syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0;)
            for (long at = 0; at < n;) {
                const auto* d = reinterpret_cast<const dirent64_record*>(buf + at);
                if (std::strcmp(d->name, ".") != 0 && std::strcmp(d->name, "..") != 0) ::unlinkat(fd, d->name, 0);
                at += d->reclen;
            }
        ::close(fd);
        if (::rmdir(dir) == 0 || errno == ENOENT) return;
    }
}

inline void remove_staged_and_reraise(int sig) {
    staging_registry& r = registry();
    if (r.committing.load()) {  // delivered to another thread than the committing one
        r.pending.store(sig);
        return;
    }
    const int saved = errno;
    for (int i = 0, n = r.count.load(); i < n; ++i) remove_staging_directory(r.dirs[i]);
    errno = saved;
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

inline constexpr int guarded_signals[] = {SIGINT, SIGTERM, SIGHUP};

}  // namespace detail

class output_set {
public:
    output_set() {
        if (detail::registry().in_use.exchange(true)) throw std::logic_error("output_set: one per process");
        for (int s : detail::guarded_signals) {
            struct sigaction a {};
            a.sa_handler = detail::remove_staged_and_reraise;
            sigemptyset(&a.sa_mask);
            ::sigaction(s, &a, &old_[index_of(s)]);
        }
    }
    output_set(const output_set&) = delete;
    output_set& operator=(const output_set&) = delete;

    /// Removes what was staged and not committed, restores the signal handlers.
    ~output_set() {
        block_signals block;
        discard();
        for (int s : detail::guarded_signals) ::sigaction(s, &old_[index_of(s)], nullptr);
        detail::registry().count.store(0);
        detail::registry().in_use.store(false);
    }

    /// Registers `final_path` as an output and returns the path to write it to (in the staging
    /// directory). Throws io_error naming the directory when it cannot be written.
    std::filesystem::path add(const std::filesystem::path& final_path) { return stage(final_path, false); }

    /// As add(), for a file that marks the set complete (a manifest, a report): the previous one is
    /// removed first and the new one moved into place last.
    std::filesystem::path add_manifest(const std::filesystem::path& final_path) { return stage(final_path, true); }

    /// Moves every staged file to its final path (creating the directories), manifests last.
    /// Files that were registered but not written are skipped, so optional outputs may be added
    /// early. Throws io_error naming the file when a move fails (the files already moved stay).
    void commit() {
        namespace fs = std::filesystem;
        detail::staging_registry& r = detail::registry();
        {
            block_signals block;  // this thread; the others see `committing`
            r.committing.store(true);
            try {
                move_into_place();
            } catch (...) {
                r.committing.store(false);
                throw;
            }
            r.committing.store(false);
        }
        if (const int sig = r.pending.exchange(0)) ::raise(sig);  // the set is whole: now honour it
    }

private:
    void move_into_place() {
        namespace fs = std::filesystem;
        std::error_code ec;
        for (const entry& e : entries_)
            if (e.manifest) fs::remove(e.final_path, ec);
        for (int pass = 0; pass < 2; ++pass)
            for (entry& e : entries_) {
                if (e.manifest != (pass == 1) || !fs::exists(e.staged, ec)) continue;
                if (!e.final_path.parent_path().empty()) fs::create_directories(e.final_path.parent_path(), ec);
                fs::rename(e.staged, e.final_path, ec);
                if (ec) throw io_error(e.final_path.string(), 0, "cannot move the finished file into place: " + ec.message());
            }
        discard();
    }

    struct entry {
        std::filesystem::path final_path, staged;
        bool manifest;
    };
    struct block_signals {
        sigset_t old{};
        block_signals() {
            sigset_t s;
            sigemptyset(&s);
            for (int sig : detail::guarded_signals) sigaddset(&s, sig);
            ::pthread_sigmask(SIG_BLOCK, &s, &old);
        }
        ~block_signals() { ::pthread_sigmask(SIG_SETMASK, &old, nullptr); }
    };

    static constexpr std::size_t index_of(int sig) {
        for (std::size_t i = 0; i < std::size(detail::guarded_signals); ++i)
            if (detail::guarded_signals[i] == sig) return i;
        return 0;
    }

    // The nearest existing ancestor of p's directory (absolute); io_error when that ancestor is a
    // file, so that commit() could not create the directories.
    static std::filesystem::path anchor_of(const std::filesystem::path& p) {
        namespace fs = std::filesystem;
        std::error_code ec;
        fs::path dir = fs::absolute(p).parent_path();
        while (!fs::exists(dir, ec) && dir != dir.root_path()) dir = dir.parent_path();
        if (!fs::is_directory(dir, ec)) throw io_error(p.string(), 0, "cannot write: " + dir.string() + " is not a directory");
        return dir;
    }

    std::filesystem::path stage(const std::filesystem::path& final_path, bool manifest) {
        namespace fs = std::filesystem;
        if (final_path.empty()) throw invalid_input("output path is empty");
        std::error_code ec;
        if (fs::is_directory(final_path, ec)) throw io_error(final_path.string(), 0, "cannot write: the path is a directory");
        const fs::path anchor = anchor_of(final_path);
        std::size_t d = 0;
        while (d < dirs_.size() && dirs_[d].anchor != anchor) ++d;
        if (d == dirs_.size()) {
            remove_stale_staging(anchor);
            const fs::path staging = anchor / (".fabsynth-stage-" + std::to_string(::getpid()));
            fs::create_directory(staging, ec);
            if (ec && !fs::is_directory(staging))
                throw io_error(final_path.string(), 0, "cannot write in " + anchor.string() + ": " + ec.message());
            dirs_.push_back({anchor, staging, 0});
            remember(staging);
        }
        staging_dir& sd = dirs_[d];
        fs::path staged = sd.path / (std::to_string(sd.files++) + "-" + final_path.filename().string());
        entries_.push_back({final_path, staged, manifest});
        return staged;
    }

    // A process that exists and has not terminated. A tool killed together with its parent may stay
    // an unreaped zombie, so "exists" (kill(pid, 0)) is not enough: a pidfd polls readable once the
    // process has terminated, reaped or not, and needs no /proc (which a container may hide).
    static bool process_alive(long pid) {
        const long fd = ::syscall(SYS_pidfd_open, static_cast<pid_t>(pid), 0u);
        if (fd >= 0) {
            pollfd p{static_cast<int>(fd), POLLIN, 0};
            const int ready = ::poll(&p, 1, 0);
            ::close(static_cast<int>(fd));
            return ready == 0;
        }
        if (errno == ESRCH) return false;
        // No pidfd (Linux < 5.3): /proc's state letter, Z or X for a terminated process.
        if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno != EPERM) return false;
        std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
        std::string line;
        if (!std::getline(stat, line)) return true;
        const std::size_t paren = line.rfind(')');  // "pid (name) S ...": the name may hold spaces
        return !(paren != std::string::npos && paren + 2 < line.size() && (line[paren + 2] == 'Z' || line[paren + 2] == 'X'));
    }

    // Staging directories of this tool family whose process is gone (SIGKILL, power loss).
    static void remove_stale_staging(const std::filesystem::path& anchor) {
        namespace fs = std::filesystem;
        std::error_code ec;
        const std::string prefix = ".fabsynth-stage-";
        for (fs::directory_iterator it(anchor, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name.rfind(prefix, 0) != 0) continue;
            const std::string pid = name.substr(prefix.size());
            if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) continue;
            const long p = std::stol(pid);
            if (p == ::getpid() || process_alive(p)) continue;
            fs::remove_all(it->path(), ec);
        }
    }

    // Keeps a staging directory for the signal handler (beyond max_dirs anchors, the next run's
    // sweep removes what an interrupted run leaves).
    void remember(const std::filesystem::path& dir) {
        detail::staging_registry& r = detail::registry();
        const int n = r.count.load();
        if (n >= detail::staging_registry::max_dirs) return;
        keep_.push_back(dir.string());
        block_signals block;
        r.dirs[n] = keep_.back().c_str();
        r.count.store(n + 1);
    }

    void discard() {
        std::error_code ec;
        for (const staging_dir& d : dirs_) std::filesystem::remove_all(d.path, ec);
        dirs_.clear();
        entries_.clear();
        detail::registry().count.store(0);
    }

    struct staging_dir {
        std::filesystem::path anchor, path;
        std::size_t files;
    };
    std::vector<staging_dir> dirs_;
    std::vector<entry> entries_;
    std::list<std::string> keep_;  // stable c_str() for the handler
    struct sigaction old_[std::size(detail::guarded_signals)]{};
};

}  // namespace fabsynth::tool
