#pragma once
// A mutex with priority inheritance, for the few locks the 1 kHz thread (SCHED_FIFO) may take: while it
// waits, whoever holds the lock runs at its priority, so a normal-priority holder cannot be pre-empted
// by everything in between (priority inversion). BasicLockable, so std::lock_guard takes it. Where the
// system does not support the protocol it is an ordinary mutex: still correct, only without the boost.
#include <pthread.h>

namespace ikebana {

class PiMutex {
public:
    PiMutex() noexcept {
        pthread_mutexattr_t attributes;
        pthread_mutexattr_init(&attributes);
        (void)pthread_mutexattr_setprotocol(&attributes, PTHREAD_PRIO_INHERIT);
        pthread_mutex_init(&mutex_, &attributes);
        pthread_mutexattr_destroy(&attributes);
    }
    ~PiMutex() { pthread_mutex_destroy(&mutex_); }
    PiMutex(const PiMutex&) = delete;
    PiMutex& operator=(const PiMutex&) = delete;

    void lock() noexcept { pthread_mutex_lock(&mutex_); }
    void unlock() noexcept { pthread_mutex_unlock(&mutex_); }
    [[nodiscard]] bool try_lock() noexcept { return pthread_mutex_trylock(&mutex_) == 0; }

private:
    pthread_mutex_t mutex_;
};

} // namespace ikebana
