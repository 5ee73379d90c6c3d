// A mutex that lends a waiting thread's priority to the thread holding it (pthread's
// PTHREAD_PRIO_INHERIT), with std::mutex's interface (std::lock_guard, std::unique_lock).
// For data a real-time thread reads while a normal thread updates it: with a plain mutex the
// real-time thread waits for the holder, and the holder waits for every other normal thread
// the scheduler runs first (priority inversion): an emulated board answering its driver late.
// Without real-time threads it behaves as std::mutex.
#pragma once

#include <pthread.h>

#include <cerrno>
#include <system_error>

namespace robot_core {

class PriorityInheritanceMutex {
 public:
  PriorityInheritanceMutex() {
    pthread_mutexattr_t attr;
    pthread_mutexattr_init(&attr);
    pthread_mutexattr_setprotocol(&attr, PTHREAD_PRIO_INHERIT);
    const int err = pthread_mutex_init(&mutex_, &attr);
    pthread_mutexattr_destroy(&attr);
    if (err != 0) throw std::system_error(err, std::generic_category(), "pthread_mutex_init (priority inheritance)");
  }
  ~PriorityInheritanceMutex() { pthread_mutex_destroy(&mutex_); }
  PriorityInheritanceMutex(const PriorityInheritanceMutex&) = delete;
  PriorityInheritanceMutex& operator=(const PriorityInheritanceMutex&) = delete;

  void lock() {
    const int err = pthread_mutex_lock(&mutex_);
    if (err != 0) throw std::system_error(err, std::generic_category(), "pthread_mutex_lock");
  }
  bool try_lock() { return pthread_mutex_trylock(&mutex_) == 0; }
  void unlock() { pthread_mutex_unlock(&mutex_); }

 private:
  pthread_mutex_t mutex_;
};

}  // namespace robot_core
