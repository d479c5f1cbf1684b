!> Images (coarrays over OpenCoarrays/MPI): the one module that holds coarrays.
!>
!> The physics code calls these procedures and never sees `[ ]`. In the serial build
!> (-fcoarray=single) there is one image, the reductions return their argument and the
!> neighbour exchange has no neighbour. Every procedure here is collective: all images call
!> it, in the same order (the time loop runs in lockstep), or none does.
module mpm_parallel
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: image_id, image_count, sum_over_images, max_over_images, min_over_images, &
        counts_of_images, exchange_neighbours, gather_on_first, agree_on_failure, end_images

    !> Sum over the images of a value of each image.
    interface sum_over_images
        module procedure sum_real, sum_reals, sum_i8, sum_i8s
    end interface sum_over_images

    !> Largest value over the images.
    interface max_over_images
        module procedure max_real, max_int
    end interface max_over_images

    !> Smallest value over the images.
    interface min_over_images
        module procedure min_real, min_int
    end interface min_over_images

    real(wp), allocatable :: inbox(:, :)[:]
        !! what the neighbours put: (1:capacity, 1) from the left neighbour, (:, 2) from the
        !! right one
    integer :: inbox_count(2)[*]
        !! number of values in each inbox
    integer :: capacity = 0
        !! size of an inbox (the same on every image)

contains

    !> This image, 1 .. image_count().
    integer function image_id()
        image_id = this_image()
    end function image_id

    !> Number of images of the run.
    integer function image_count()
        image_count = num_images()
    end function image_count

    subroutine sum_real(x)
        real(wp), intent(inout) :: x
            !! this image's value; on return the sum over the images
        if (num_images() > 1) call co_sum(x)
    end subroutine sum_real

    subroutine sum_reals(x)
        real(wp), intent(inout) :: x(:)
            !! this image's values; on return the sums over the images
        if (num_images() > 1) call co_sum(x)
    end subroutine sum_reals

    subroutine sum_i8(x)
        integer(i8), intent(inout) :: x
            !! this image's value; on return the sum over the images
        if (num_images() > 1) call co_sum(x)
    end subroutine sum_i8

    subroutine sum_i8s(x)
        integer(i8), intent(inout) :: x(:)
            !! this image's values; on return the sums over the images
        if (num_images() > 1) call co_sum(x)
    end subroutine sum_i8s

    subroutine max_real(x)
        real(wp), intent(inout) :: x
            !! this image's value; on return the largest over the images
        if (num_images() > 1) call co_max(x)
    end subroutine max_real

    subroutine max_int(x)
        integer, intent(inout) :: x
            !! this image's value; on return the largest over the images
        if (num_images() > 1) call co_max(x)
    end subroutine max_int

    subroutine min_real(x)
        real(wp), intent(inout) :: x
            !! this image's value; on return the smallest over the images
        if (num_images() > 1) call co_min(x)
    end subroutine min_real

    subroutine min_int(x)
        integer, intent(inout) :: x
            !! this image's value; on return the smallest over the images
        if (num_images() > 1) call co_min(x)
    end subroutine min_int

    !> The count of every image: counts(i) is image i's n.
    function counts_of_images(n) result(counts)
        integer, intent(in) :: n
            !! this image's count
        integer(i8), allocatable :: counts(:)

        allocate (counts(num_images()))
        counts = 0
        counts(this_image()) = n
        if (num_images() > 1) call co_sum(counts)
    end function counts_of_images

    !> Send a buffer to each neighbour and receive theirs (images along a line: `left` and
    !> `right` are this image -1 and +1, or 0 at the ends of the line; a neighbour's `right`
    !> must be this image and the other way round).
    subroutine exchange_neighbours(left, right, send_left, send_right, recv_left, recv_right, &
        most)
        integer, intent(in) :: left
            !! image on the left, 0 for none
        integer, intent(in) :: right
            !! image on the right, 0 for none
        real(wp), intent(in) :: send_left(:)
            !! values for the left neighbour
        real(wp), intent(in) :: send_right(:)
            !! values for the right neighbour
        real(wp), allocatable, intent(out) :: recv_left(:)
            !! what the left neighbour sent (empty without one)
        real(wp), allocatable, intent(out) :: recv_right(:)
            !! what the right neighbour sent (empty without one)
        integer, intent(in), optional :: most
            !! the most values any image sends, the same number on every image (a small
            !! fixed message): the images then need not agree on the inbox size first

        integer :: need, n
        integer, allocatable :: partners(:)

        if (num_images() == 1) then
            allocate (recv_left(0), recv_right(0))
            return
        end if
        if (present(most)) then
            ! the same on every image: no reduction needed to agree on the inbox size
            need = max(1, most)
        else
            need = max(1, size(send_left), size(send_right))
            call co_max(need)
        end if
        if (need > capacity) then
            ! collective: every image takes the same decision from the same numbers
            if (allocated(inbox)) deallocate (inbox)
            capacity = max(need, 2*capacity)
            allocate (inbox(capacity, 2)[*])
        end if
        partners = pack([left, right], [left, right] > 0)
        ! the neighbours have read what was put in their inboxes the last time
        if (size(partners) > 0) sync images(partners)
        if (left > 0) then
            n = size(send_left)
            inbox_count(2)[left] = n
            if (n > 0) inbox(1:n, 2)[left] = send_left
        end if
        if (right > 0) then
            n = size(send_right)
            inbox_count(1)[right] = n
            if (n > 0) inbox(1:n, 1)[right] = send_right
        end if
        if (size(partners) > 0) sync images(partners)
        if (left > 0) then
            recv_left = inbox(1:inbox_count(1), 1)
        else
            allocate (recv_left(0))
        end if
        if (right > 0) then
            recv_right = inbox(1:inbox_count(2), 2)
        else
            allocate (recv_right(0))
        end if
    end subroutine exchange_neighbours

    !> The values of every image one after the other, in image order, on image 1 (`recv` is
    !> empty on the others). For the rare whole-run writes (state files): image 1 holds them
    !> all, and the staging buffer is released after.
    subroutine gather_on_first(send, recv)
        real(wp), intent(in) :: send(:)
            !! this image's values
        real(wp), allocatable, intent(out) :: recv(:)
            !! on image 1 the values of images 1, 2, ...; empty on the others

        integer(i8), allocatable :: counts(:)
        integer(i8) :: offset
        integer :: need, k, n

        if (num_images() == 1) then
            recv = send
            return
        end if
        counts = counts_of_images(size(send))
        need = max(1, int(maxval(counts)))
        if (need > capacity) then
            if (allocated(inbox)) deallocate (inbox)
            capacity = need
            allocate (inbox(capacity, 2)[*])
        end if
        ! no image still reads its inbox from an exchange
        sync all
        if (size(send) > 0) inbox(1:size(send), 1) = send
        sync all
        if (this_image() == 1) then
            allocate (recv(sum(counts)))
            offset = 0
            do k = 1, num_images()
                n = int(counts(k))
                if (n > 0) recv(offset + 1:offset + n) = inbox(1:n, 1)[k]
                offset = offset + n
            end do
        else
            allocate (recv(0))
        end if
        ! image 1 has read every inbox; release the staging buffer (collective)
        deallocate (inbox)
        capacity = 0
    end subroutine gather_on_first

    !> Make a failure the decision of every image: returns the largest code of the images
    !> (0: none failed) and whether this image is the one that reports it (the first image
    !> with that code), so one message is printed.
    subroutine agree_on_failure(code, reporter)
        integer, intent(inout) :: code
            !! this image's exit code (0: no failure); on return the largest over the images
        logical, intent(out) :: reporter
            !! this image prints the message

        integer :: mine, first

        mine = code
        reporter = code /= 0
        if (num_images() == 1) return
        call co_max(code)
        first = huge(1)
        if (code /= 0 .and. mine == code) first = this_image()
        call co_min(first)
        reporter = code /= 0 .and. first == this_image()
    end subroutine agree_on_failure

    !> End a coarray run on every image with an exit code (all images call it; app/main.f90
    !> then stops). In a coarray run `stop code` is an MPI abort on each image: the images
    !> finish MPI normally instead and leave with the code, so the launcher passes it on
    !> without an abort report. In the serial build it returns and the caller stops.
    subroutine end_images(code)
#ifdef MPM_COARRAY
        use, intrinsic :: iso_c_binding, only: c_int
#endif
        integer, intent(in) :: code
            !! exit code (0: success)
#ifdef MPM_COARRAY
        interface
            subroutine mpi_finalize(ierror)
                integer, intent(out) :: ierror
            end subroutine mpi_finalize
            subroutine c_exit(status) bind(c, name="exit")
                import :: c_int
                integer(c_int), value :: status
            end subroutine c_exit
        end interface
        integer :: ierror

        sync all
        call mpi_finalize(ierror)
        call c_exit(int(code, c_int))
#endif
    end subroutine end_images

end module mpm_parallel
