!> The image primitives of mpm_parallel on several images (cafrun -np 2 or more): reductions,
!> the neighbour exchange (also of empty and growing buffers), the gather on image 1, and the
!> agreement on a failure of one image. Prints the cost of an exchange (not asserted).
program test_parallel
    use mpm_kinds, only: wp, i8
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_parallel, only: image_id, image_count, sum_over_images, max_over_images, &
        min_over_images, counts_of_images, exchange_neighbours, gather_on_first, &
        agree_on_failure
    use mpm_clock, only: wall_time
    implicit none

    type(test_suite_type) :: suite
    integer :: me, n

    me = image_id()
    n = image_count()
    call new_suite(suite, "parallel (image "//achar(iachar("0") + min(me, 9))//")")
    call test_reductions()
    call test_exchange()
    call test_gather()
    call test_agreement()
    call time_exchange()
    call finish(suite)

contains

    subroutine test_reductions()
        real(wp) :: x, xs(2)
        integer :: k
        integer(i8) :: total
        integer(i8), allocatable :: counts(:)

        call check(suite, n >= 2, "run on 2 or more images (cafrun -np 2)")
        x = real(me, wp)
        call sum_over_images(x)
        call check_close(suite, x, real(n*(n + 1)/2, wp), 0.0_wp, "sum over images")
        xs = [real(me, wp), -real(me, wp)]
        call sum_over_images(xs)
        call check_close(suite, xs(2), -real(n*(n + 1)/2, wp), 0.0_wp, "sum of an array")
        x = real(me, wp)
        call max_over_images(x)
        call check_close(suite, x, real(n, wp), 0.0_wp, "max over images")
        k = me
        call min_over_images(k)
        call check(suite, k == 1, "min over images (integer)")
        total = int(me, i8)
        call sum_over_images(total)
        call check(suite, total == int(n*(n + 1)/2, i8), "sum of integer(i8)")
        counts = counts_of_images(10*me)
        call check(suite, size(counts) == n .and. all(counts == [(10_i8*k, k = 1, n)]), &
            "counts of every image")
    end subroutine test_reductions

    subroutine test_exchange()
        real(wp), allocatable :: send_left(:), send_right(:), recv_left(:), recv_right(:)
        integer :: left, right, round, m, k

        left = merge(me - 1, 0, me > 1)
        right = merge(me + 1, 0, me < n)
        ! sizes that differ by side and round, empty ones, and one that grows the inbox
        do round = 1, 3
            m = merge(100000, 3*me + round, round == 3)
            send_left = [(1000.0_wp*me + k, k = 1, m)]
            send_right = [(-1000.0_wp*me - k, k = 1, m + 1)]
            if (round == 2 .and. me == 1) deallocate (send_right)
            if (round == 2 .and. me == 1) allocate (send_right(0))
            call exchange_neighbours(left, right, send_left, send_right, recv_left, recv_right)
            if (left > 0) then
                ! the left neighbour sent its send_right
                m = merge(100000, 3*left + round, round == 3)
                if (round == 2 .and. left == 1) then
                    call check(suite, size(recv_left) == 0, "empty buffer from the left")
                else
                    call check(suite, size(recv_left) == m + 1, "size of the left buffer")
                    if (size(recv_left) == m + 1) call check(suite, all(recv_left == &
                        [(-1000.0_wp*left - k, k = 1, m + 1)]), "values from the left")
                end if
            else
                call check(suite, size(recv_left) == 0, "nothing from the left end")
            end if
            if (right > 0) then
                m = merge(100000, 3*right + round, round == 3)
                call check(suite, size(recv_right) == m, "size of the right buffer")
                if (size(recv_right) == m) call check(suite, all(recv_right == &
                    [(1000.0_wp*right + k, k = 1, m)]), "values from the right")
            else
                call check(suite, size(recv_right) == 0, "nothing from the right end")
            end if
        end do
    end subroutine test_exchange

    subroutine test_gather()
        real(wp), allocatable :: mine(:), gathered(:), expected(:)
        integer :: k, j

        mine = [(real(100*me + k, wp), k = 1, me)]
        call gather_on_first(mine, gathered)
        if (me == 1) then
            expected = [((real(100*k + j, wp), j = 1, k), k = 1, n)]
            call check(suite, size(gathered) == size(expected), "gather: size on image 1")
            if (size(gathered) == size(expected)) call check(suite, all(gathered == expected), &
                "gather: values in image order")
        else
            call check(suite, size(gathered) == 0, "gather: nothing on the other images")
        end if
    end subroutine test_gather

    subroutine test_agreement()
        integer :: code
        logical :: reporter

        ! image 2 fails with code 3, the last image with code 2: every image gets 3, and
        ! image 2 alone reports
        code = 0
        if (me == 2) code = 3
        if (me == n .and. n > 2) code = 2
        call agree_on_failure(code, reporter)
        call check(suite, code == 3, "agreed code is the largest")
        call check(suite, reporter .eqv. (me == 2), "one reporter: the image with that code")
        code = 0
        call agree_on_failure(code, reporter)
        call check(suite, code == 0 .and. .not. reporter, "no failure, no reporter")
    end subroutine test_agreement

    subroutine time_exchange()
        real(wp), allocatable :: send(:), recv_left(:), recv_right(:)
        real(wp) :: t0, x
        integer :: k, left, right
        integer, parameter :: rounds = 2000

        left = merge(me - 1, 0, me > 1)
        right = merge(me + 1, 0, me < n)
        allocate (send(3000))
        send = 1.0_wp
        t0 = wall_time()
        do k = 1, rounds
            call exchange_neighbours(left, right, send, send, recv_left, recv_right)
        end do
        t0 = (wall_time() - t0)/rounds
        x = 1.0_wp
        if (me == 1) write (*, "(a,f8.2,a)") "exchange of 3000 values: ", 1.0e6_wp*t0, &
            " us per call"
        t0 = wall_time()
        do k = 1, rounds
            call sum_over_images(x)
        end do
        t0 = (wall_time() - t0)/rounds
        if (me == 1) write (*, "(a,f8.2,a)") "sum over images of a scalar: ", 1.0e6_wp*t0, &
            " us per call"
    end subroutine time_exchange

end program test_parallel
