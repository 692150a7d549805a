// SPDX-License-Identifier: Apache-2.0
// UniqueFd: closes its descriptor exactly once, hands it on when moved or released. Whether a
// descriptor is open is asked of the kernel (fcntl(F_GETFD) fails with EBADF once it is closed).

#include "navmap/ipc/net/unique_fd.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <utility>

#include "open_fds.h"

namespace {

using navmap::ipc::net::UniqueFd;

bool isOpen(int fd) {
    errno = 0;
    const bool open = ::fcntl(fd, F_GETFD) != -1;
    return open || errno != EBADF;
}

int newFd() {
    const int fd = ::eventfd(0, EFD_CLOEXEC);
    EXPECT_GE(fd, 0);
    return fd;
}

TEST(UniqueFdTest, DefaultOwnsNothing) {
    const UniqueFd fd;
    EXPECT_FALSE(fd.valid());
    EXPECT_EQ(fd.get(), -1);
}

TEST(UniqueFdTest, DestructorClosesTheDescriptor) {
    const int raw = newFd();
    {
        const UniqueFd fd(raw);
        EXPECT_TRUE(fd.valid());
        EXPECT_EQ(fd.get(), raw);
        EXPECT_TRUE(isOpen(raw));
    }
    EXPECT_FALSE(isOpen(raw));
}

TEST(UniqueFdTest, ClosesExactlyOnce) {
    // After the first close the kernel hands the same number to the next descriptor; a second
    // close by any UniqueFd (the moved-from one, or a reset) would close that newcomer.
    const int raw = newFd();
    UniqueFd first(raw);
    UniqueFd second(std::move(first));
    second.reset();
    EXPECT_FALSE(isOpen(raw));
    const int reused = newFd();
    ASSERT_EQ(reused, raw) << "the kernel gives the lowest free number";
    first.reset();  // NOLINT(bugprone-use-after-move): a moved-from UniqueFd is empty and resettable
    second.reset();
    { const UniqueFd gone(std::move(first)); }
    EXPECT_TRUE(isOpen(reused));
    ::close(reused);
}

TEST(UniqueFdTest, MoveConstructionTransfersOwnership) {
    const int raw = newFd();
    UniqueFd from(raw);
    {
        const UniqueFd to(std::move(from));
        EXPECT_FALSE(from.valid());  // NOLINT(bugprone-use-after-move): the moved-from state is the point
        EXPECT_EQ(to.get(), raw);
        EXPECT_TRUE(isOpen(raw));
    }
    EXPECT_FALSE(isOpen(raw));
}

TEST(UniqueFdTest, MoveAssignmentClosesTheOldDescriptorAndTakesTheNew) {
    const int old_raw = newFd();
    const int new_raw = newFd();
    UniqueFd target(old_raw);
    UniqueFd source(new_raw);
    target = std::move(source);
    EXPECT_FALSE(isOpen(old_raw));
    EXPECT_TRUE(isOpen(new_raw));
    EXPECT_EQ(target.get(), new_raw);
    EXPECT_FALSE(source.valid());  // NOLINT(bugprone-use-after-move)
    target.reset();
    EXPECT_FALSE(isOpen(new_raw));
}

TEST(UniqueFdTest, SelfMoveAssignmentKeepsTheDescriptor) {
    const int raw = newFd();
    UniqueFd fd(raw);
    UniqueFd& alias = fd;
    fd = std::move(alias);
    EXPECT_EQ(fd.get(), raw);
    EXPECT_TRUE(isOpen(raw));
}

TEST(UniqueFdTest, ReleaseHandsTheDescriptorOnWithoutClosing) {
    const int raw = newFd();
    int released = -1;
    {
        UniqueFd fd(raw);
        released = fd.release();
        EXPECT_FALSE(fd.valid());
    }
    EXPECT_EQ(released, raw);
    EXPECT_TRUE(isOpen(raw));
    ::close(raw);
}

TEST(UniqueFdTest, ResetClosesTheOldAndOwnsTheNew) {
    const int a = newFd();
    const int b = newFd();
    UniqueFd fd(a);
    fd.reset(b);
    EXPECT_FALSE(isOpen(a));
    EXPECT_TRUE(isOpen(b));
    fd.reset(b);  // the same descriptor again: still owned, not closed
    EXPECT_TRUE(isOpen(b));
    fd.reset();
    EXPECT_FALSE(isOpen(b));
    EXPECT_FALSE(fd.valid());
}

TEST(UniqueFdTest, LeavesNoDescriptorBehind) {
    const int before = navmap::test::countOpenFds();
    for (int i = 0; i < 64; ++i) {
        UniqueFd a(newFd());
        UniqueFd b(std::move(a));
        a = std::move(b);
        b.reset(newFd());  // NOLINT(bugprone-use-after-move): moved-from is empty, reset reuses it
    }
    EXPECT_EQ(navmap::test::countOpenFds(), before);
}

}  // namespace
