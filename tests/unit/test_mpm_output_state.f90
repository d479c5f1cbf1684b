!> Tests of mpm_state: state files saved into an output folder and loaded back bit for bit, and
!> the files load_state refuses (the particle output: test_mpm_output).
!>
!> Files go to a fresh folder under $TMPDIR (default /tmp), deleted at the end unless
!> MPM_TEST_KEEP is set.
program test_mpm_output_state
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_case, only: case_type
    use mpm_particles, only: particles_type, new_particles
    use mpm_grid, only: grid_type, new_grid
    use mpm_output, only: output_writer_type, new_output_writer, write_output
    use mpm_state, only: save_state, load_state
    use mpm_filesystem, only: make_directory, file_exists
    use mpm_hdf5, only: hdf5_location_type, hdf5_open_file, hdf5_write_attribute, hdf5_close
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish
    use mpm_testing_output, only: tiny_case, fill_particles, open_hdf5_objects, same_bits_1d, &
        same_bits_2d, same_bits_3d, open_test_folder, close_test_folder
    implicit none

    character(len=*), parameter :: files(*) = [character(len=40) :: "states/d2/state.h5", &
        "states/d3/state.h5", "states/empty.h5", "states/remap.h5", "states/refuse.h5", &
        "states/text.h5", "states/v2.h5", "states/outside.h5", &
        "states/output/particles_000000.h5", "states/output/tiny.xdmf"]
        !! the files this test leaves, deleted at the end
    character(len=*), parameter :: folders(*) = [character(len=16) :: "states/d2", "states/d3", &
        "states/output", "states", ""]
        !! the folders it makes, deepest first

    type(test_suite_type) :: suite
    character(len=:), allocatable :: root
    logical :: keep

    call new_suite(suite, "mpm_output_state")
    call open_test_folder(suite, "mpm_output_state_test", root, keep)

    call test_state_round_trip(suite, root)
    call test_state_refusals(suite, root)

    call close_test_folder(suite, root, keep, files, folders)
    call finish(suite)

contains

    subroutine test_state_round_trip(suite, root)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: root

        type(case_type) :: case, other
        type(particles_type) :: saved, loaded
        type(error_type), allocatable :: error
        real(wp) :: time
        integer :: step, dim
        character(len=:), allocatable :: path

        do dim = 2, 3
            call tiny_case(case)
            if (dim == 3) then
                case%dim = 3
                case%domain%ncells = [4, 3, 2]
                case%domain%origin(3) = 7.0_wp
            end if
            call fill_particles(suite, case, 6, saved)
            path = root//"/states/d"//achar(iachar("0") + dim)//"/state.h5"
            call save_state(path, case, saved, 1.5_wp, 42, error)
            call check(suite, .not. allocated(error), "save_state creates its folder")
            if (allocated(error)) write (*, "(a)") error%message
            call check(suite, .not. file_exists(path//".tmp"), "no state .tmp left")

            call load_state(path, case, loaded, time, step, error)
            call check(suite, .not. allocated(error), "load_state")
            if (allocated(error)) then
                write (*, "(a)") error%message
                cycle
            end if
            call check(suite, time == 1.5_wp .and. step == 42, "time and step")
            call check(suite, loaded%n == saved%n .and. loaded%dim == saved%dim .and. &
                loaded%nstress == saved%nstress, "sizes")
            call check(suite, same_bits_2d(loaded%x, saved%x), "x bit for bit")
            call check(suite, same_bits_2d(loaded%u, saved%u), "u bit for bit")
            call check(suite, same_bits_2d(loaded%v, saved%v), "v bit for bit")
            call check(suite, same_bits_1d(loaded%mass, saved%mass), "mass bit for bit")
            call check(suite, same_bits_1d(loaded%volume, saved%volume), "volume bit for bit")
            call check(suite, same_bits_1d(loaded%volume0, saved%volume0), "volume0 bit for bit")
            call check(suite, same_bits_2d(loaded%stress, saved%stress), "stress bit for bit")
            call check(suite, same_bits_2d(loaded%strain, saved%strain), "strain bit for bit")
            call check(suite, same_bits_3d(loaded%f, saved%f), "f bit for bit")
            call check(suite, same_bits_2d(loaded%lp0, saved%lp0), "lp0 bit for bit")
            call check(suite, all(loaded%material == saved%material), "material indices")
        end do

        ! No particles: empty datasets round-trip too
        call tiny_case(case)
        call new_particles(saved, 2, 0, error)
        path = root//"/states/empty.h5"
        call save_state(path, case, saved, 0.5_wp, 3, error)
        call check(suite, .not. allocated(error), "save_state with no particles")
        call load_state(path, case, loaded, time, step, error)
        call check(suite, .not. allocated(error), "load_state with no particles")
        if (.not. allocated(error)) then
            call check(suite, loaded%n == 0 .and. size(loaded%x, 2) == 0 .and. &
                time == 0.5_wp .and. step == 3, "empty state")
        end if

        ! Same grid, materials listed in another order plus a new one: indices follow names
        call tiny_case(case)
        call fill_particles(suite, case, 6, saved)
        path = root//"/states/remap.h5"
        call save_state(path, case, saved, 0.0_wp, 0, error)
        call check(suite, .not. allocated(error), "save_state for remap")
        call tiny_case(other)
        deallocate (other%materials)
        allocate (other%materials(3))
        other%materials(1)%name = "clay"
        other%materials(2)%name = "rock"
        other%materials(3)%name = "sand"
        call load_state(path, other, loaded, time, step, error)
        call check(suite, .not. allocated(error), "load_state with reordered materials")
        if (.not. allocated(error)) then
            call check(suite, all(pack(loaded%material, saved%material == 1) == 3), &
                "sand remapped to 3")
            call check(suite, all(pack(loaded%material, saved%material == 2) == 1), &
                "clay remapped to 1")
        end if
    end subroutine test_state_round_trip

    subroutine test_state_refusals(suite, root)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: root

        type(case_type) :: case, other
        type(particles_type) :: saved, loaded
        type(error_type), allocatable :: error
        type(hdf5_location_type) :: file
        type(grid_type) :: grid
        type(output_writer_type) :: writer
        real(wp) :: time
        integer :: step, unit
        character(len=:), allocatable :: path

        call tiny_case(case)
        call fill_particles(suite, case, 3, saved)
        path = root//"/states/refuse.h5"
        call save_state(path, case, saved, 2.0_wp, 7, error)
        call check(suite, .not. allocated(error), "save_state for refusals")

        other = case
        other%domain%dx = 0.25_wp
        call expect_refusal(path, other, ["dx = 0.5 m ", "dx = 0.25 m"], "different dx")

        other = case
        other%domain%dx = 0.5_wp*(1.0_wp + 1.0e-14_wp)
        call load_state(path, other, loaded, time, step, error)
        call check(suite, .not. allocated(error), "dx within 1e-12 relative is accepted")

        other = case
        other%dim = 3
        call expect_refusal(path, other, ["state has dimension 2", "case has dimension 3 "], &
            "different dimension")

        other = case
        other%domain%ncells = [4, 6, 1]
        call expect_refusal(path, other, ["ncells = 4 3", "ncells = 4 6"], "different ncells")

        other = case
        other%domain%origin(2) = -2.0_wp
        call expect_refusal(path, other, ["origin = (1, -1)", "origin = (1, -2)"], &
            "different origin")

        other = case
        other%materials(2)%name = "rock"
        call expect_refusal(path, other, [character(len=36) :: "material 'clay'", &
            "the case has: 'sand', 'rock'"], "missing material")

        ! not HDF5
        open (newunit=unit, file=root//"/states/text.h5", status="replace", action="write")
        write (unit, "(a)") "this is not HDF5"
        close (unit)
        call expect_refusal(root//"/states/text.h5", case, ["not an HDF5 file"], "text file")
        call expect_refusal(root//"/states/none.h5", case, ["does not exist"], "missing file")
        ! an output file is HDF5 but not a state
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid for an output file")
        call make_directory(root//"/states/output", error)
        call new_output_writer(writer, case, root//"/states/output", error)
        call check(suite, .not. allocated(error), "new_output_writer for an output file")
        call write_output(writer, 10, 0.0_wp, saved, grid, error)
        call check(suite, .not. allocated(error), "write_output of an output file")
        call expect_refusal(root//"/states/output/particles_000000.h5", case, &
            ["not an mpm-geo state file"], "output file")

        ! a future format_version
        call save_state(root//"/states/v2.h5", case, saved, 2.0_wp, 7, error)
        call hdf5_open_file(root//"/states/v2.h5", file, error, writable=.true.)
        call check(suite, .not. allocated(error), "reopen state for writing")
        if (.not. allocated(error)) then
            call hdf5_write_attribute(file, "format_version", 2, error)
            call hdf5_close(file, error)
        end if
        call expect_refusal(root//"/states/v2.h5", case, ["format_version 2 is not"], &
            "format_version 2")

        ! a particle outside the domain (x max is 1 + 4 * 0.5 = 3)
        saved%x(1, 2) = 3.25_wp
        call save_state(root//"/states/outside.h5", case, saved, 2.0_wp, 7, error)
        call expect_refusal(root//"/states/outside.h5", case, [character(len=26) :: &
            "particle 2 at (3.25,", "outside the case domain"], "particle outside")
        call check(suite, open_hdf5_objects() == 0, &
            "save_state and load_state (also refusing) leave no HDF5 object open")
    end subroutine test_state_refusals

    !> load_state must fail with exit_input, a message naming the file and each part.
    subroutine expect_refusal(path, case, parts, what)
        character(len=*), intent(in) :: path
        type(case_type), intent(in) :: case
        character(len=*), intent(in) :: parts(:)
        character(len=*), intent(in) :: what

        type(particles_type) :: loaded
        type(error_type), allocatable :: error
        real(wp) :: time
        integer :: step, i

        call load_state(path, case, loaded, time, step, error)
        call check(suite, allocated(error), "load_state refuses: "//what)
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, "exit_input code: "//what)
        call check_contains(suite, error%message, "'"//path//"'", "message names the file: "//what)
        do i = 1, size(parts)
            call check_contains(suite, error%message, trim(parts(i)), what)
        end do
    end subroutine expect_refusal

end program test_mpm_output_state
