!> Helpers of the output and state-file tests (test_mpm_output, test_mpm_output_state): a
!> small 2D case and particles with a distinct value in every element, a count of the open
!> HDF5 objects, bitwise comparison of arrays, and the removal of a test's folder.
module mpm_testing_output
    use, intrinsic :: iso_c_binding, only: c_char, c_int
    use hdf5, only: hid_t, size_t, h5open_f, h5fget_obj_count_f, h5f_obj_all_f
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type
    use mpm_case, only: case_type
    use mpm_particles, only: particles_type, new_particles
    use mpm_filesystem, only: remove_file, c_string
    use mpm_testing, only: test_suite_type, check, temporary_folder
    implicit none
    private
    public :: tiny_case, fill_particles, open_hdf5_objects, same_bits_1d, same_bits_2d, &
        same_bits_3d, delete_tree, open_test_folder, close_test_folder

    ! allow(assumed-size, assumed-size-character-intent): C strings passed to libc
    interface
        function c_rmdir(path) bind(c, name="rmdir") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: status
        end function c_rmdir
    end interface

contains

    !> A 2D case of 4 x 3 cells of 0.5 m from (1, -1), materials sand and clay.
    subroutine tiny_case(case)
        type(case_type), intent(out) :: case

        case%name = "tiny"
        case%dim = 2
        case%domain%ncells = [4, 3, 1]
        case%domain%dx = 0.5_wp
        case%domain%origin = [1.0_wp, -1.0_wp, 0.0_wp]
        allocate (case%materials(2))
        case%materials(1)%name = "sand"
        case%materials(2)%name = "clay"
        case%output%fields = .true.
        case%output%grid = .true.
    end subroutine tiny_case

    !> n particles inside the case domain with a distinct value in every array element.
    subroutine fill_particles(suite, case, n, particles)
        type(test_suite_type), intent(inout) :: suite
            !! the suite that counts the check
        type(case_type), intent(in) :: case
        integer, intent(in) :: n
        type(particles_type), intent(out) :: particles

        integer :: p, d, c, nmat
        type(error_type), allocatable :: error

        call new_particles(particles, case%dim, n, error)
        call check(suite, .not. allocated(error), "new_particles")
        nmat = size(case%materials)
        do p = 1, n
            do d = 1, case%dim
                ! strictly inside the domain
                particles%x(d, p) = case%domain%origin(d) + case%domain%ncells(d)*case%domain%dx* &
                    modulo(0.1_wp + 0.13_wp*p + 0.37_wp*d, 1.0_wp)
                particles%u(d, p) = 1.0e-3_wp*(10*p + d)
                particles%v(d, p) = -0.5_wp*p + 0.01_wp*d
                particles%lp0(d, p) = 0.125_wp + 1.0e-3_wp*(p + d)
                do c = 1, case%dim
                    particles%f(c, d, p) = merge(1.0_wp, 0.0_wp, c == d) + 1.0e-4_wp*(p + 3*c + d)
                end do
            end do
            do c = 1, particles%nstress
                particles%stress(c, p) = -1000.0_wp*c - p/3.0_wp
                particles%strain(c, p) = 1.0e-4_wp*(c + 10*p)/7.0_wp
            end do
            particles%mass(p) = 2.0_wp + p/9.0_wp
            particles%volume(p) = 0.0625_wp*p/11.0_wp
            particles%volume0(p) = 0.0625_wp*p/13.0_wp
            particles%material(p) = 1 + mod(p + 1, nmat)
        end do
    end subroutine fill_particles

    !> Number of HDF5 files, groups, datasets, types and attributes open in the process
    !> (h5open_f itself leaves none).
    integer function open_hdf5_objects() result(count)
        integer(size_t) :: objects
        integer :: hdferr

        call h5fget_obj_count_f(int(h5f_obj_all_f, hid_t), h5f_obj_all_f, objects, hdferr)
        count = int(objects)
        if (hdferr /= 0) count = -1
    end function open_hdf5_objects

    !> Whether a and b have the same shape and the same bits in every element.
    logical function same_bits_1d(a, b)
        real(wp), intent(in) :: a(:), b(:)
        same_bits_1d = size(a) == size(b)
        if (same_bits_1d) same_bits_1d = all(transfer(a, 0_i8, size(a)) == &
            transfer(b, 0_i8, size(b)))
    end function same_bits_1d

    logical function same_bits_2d(a, b)
        real(wp), intent(in) :: a(:, :), b(:, :)
        same_bits_2d = all(shape(a) == shape(b))
        if (same_bits_2d) same_bits_2d = all(transfer(a, 0_i8, size(a)) == &
            transfer(b, 0_i8, size(b)))
    end function same_bits_2d

    logical function same_bits_3d(a, b)
        real(wp), intent(in) :: a(:, :, :), b(:, :, :)
        same_bits_3d = all(shape(a) == shape(b))
        if (same_bits_3d) same_bits_3d = all(transfer(a, 0_i8, size(a)) == &
            transfer(b, 0_i8, size(b)))
    end function same_bits_3d

    !> Delete the given files under root, then the given folders, deepest first ("" is root).
    subroutine delete_tree(root, files, folders, error)
        character(len=*), intent(in) :: root
            !! the test's temporary folder
        character(len=*), intent(in) :: files(:)
            !! files written by the test, relative to root
        character(len=*), intent(in) :: folders(:)
            !! folders made by the test, relative to root, deepest first
        type(error_type), allocatable, intent(out) :: error
            !! set when a file or folder cannot be removed

        integer :: i
        character(len=:), allocatable :: path
        do i = 1, size(files)
            call remove_file(root//"/"//trim(files(i)), error)
            if (allocated(error)) return
        end do
        do i = 1, size(folders)
            path = root
            if (len_trim(folders(i)) > 0) path = root//"/"//trim(folders(i))
            if (c_rmdir(c_string(path)) /= 0) then
                allocate (error)
                error%message = "cannot remove the folder "//path
                return
            end if
        end do
    end subroutine delete_tree

    !> Open the HDF5 library and make the test's temporary folder, $TMPDIR/PREFIX_XXXXXX;
    !> keep it at the end when MPM_TEST_KEEP is set.
    subroutine open_test_folder(suite, prefix, root, keep)
        type(test_suite_type), intent(inout) :: suite
            !! the suite that counts the check
        character(len=*), intent(in) :: prefix
            !! start of the folder's name
        character(len=:), allocatable, intent(out) :: root
            !! the folder made
        logical, intent(out) :: keep
            !! MPM_TEST_KEEP is set: close_test_folder leaves the folder

        integer :: hdferr

        call h5open_f(hdferr)
        call check(suite, hdferr == 0, "h5open_f")
        root = temporary_folder(prefix)
        write (*, "(a)") "temporary folder: "//root
        call get_environment_variable("MPM_TEST_KEEP", status=hdferr)
        keep = hdferr == 0
    end subroutine open_test_folder

    !> Delete the test's files and folders (delete_tree) unless it keeps them.
    subroutine close_test_folder(suite, root, keep, files, folders)
        type(test_suite_type), intent(inout) :: suite
            !! the suite that counts the check
        character(len=*), intent(in) :: root
            !! the test's temporary folder
        logical, intent(in) :: keep
            !! leave the folder (MPM_TEST_KEEP)
        character(len=*), intent(in) :: files(:)
            !! files written by the test, relative to root
        character(len=*), intent(in) :: folders(:)
            !! folders made by the test, relative to root, deepest first

        type(error_type), allocatable :: error

        if (keep) return
        call delete_tree(root, files, folders, error)
        call check(suite, .not. allocated(error), "temporary folder deleted")
        if (allocated(error)) write (*, "(a)") error%message
    end subroutine close_test_folder

end module mpm_testing_output
