!> State files (mpm_state) against the particle field table (mpm_particles): a state written
!> and read back holds every saved field of the table bit for bit, field by field (with the
!> APIC affine velocities and the material state); fields the table does not save stay out;
!> fields a run dropped come back as zeros; a case with more state variables gets the file's
!> first; a state that does not fit the case, or lacks a field the table requires, is refused
!> with exit_input and a message that names the file and the reason.
!>
!> Files go to a fresh folder under $TMPDIR (default /tmp), deleted at the end.
program test_mpm_state
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
    use hdf5, only: hid_t, h5open_f, h5fopen_f, h5fclose_f, h5f_acc_rdwr_f, h5ldelete_f
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_case, only: case_type
    use mpm_particles, only: particles_type, new_particles, particle_field_type, &
        particle_field_count, particle_field, field_index, field_held, get_field, &
        get_field_integers, put_field, put_field_integers, hold_field, values_per_particle, &
        created_particle_bytes
    use mpm_state, only: save_state, load_state, state_particle_count
    use mpm_filesystem, only: file_exists, remove_file
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish, &
        temporary_folder
    implicit none

    ! allow(assumed-size, assumed-size-character-intent): a C string passed to libc
    interface
        function c_rmdir(path) bind(c, name="rmdir") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: status
        end function c_rmdir
    end interface

    type(test_suite_type) :: suite
    character(len=:), allocatable :: root
    character(len=256) :: written(16)
    integer :: nwritten, i, hdferr
    type(error_type), allocatable :: error

    call new_suite(suite, "mpm_state")
    call h5open_f(hdferr)
    call check(suite, hdferr == 0, "h5open_f")
    root = temporary_folder("mpm_state_test")
    nwritten = 0
    call test_table()
    call test_round_trip(2)
    call test_round_trip(3)
    call test_dropped_fields()
    call test_more_state_variables()
    call test_type_change()
    call test_refusals()
    do i = 1, nwritten
        call remove_file(trim(written(i)), error)
        call check(suite, .not. allocated(error), "remove "//trim(written(i)))
    end do
    call check(suite, c_rmdir(root//c_null_char) == 0, "temporary folder removed")
    call finish(suite)

contains

    !> A 2D case of 4 x 3 cells of 0.5 m from (1, -1) (3D: 4 x 3 x 2 from (1, -1, 7)),
    !> materials sand and clay.
    subroutine small_case(case, dim)
        type(case_type), intent(out) :: case
        integer, intent(in) :: dim

        case%name = "small"
        case%dim = dim
        case%domain%ncells = [4, 3, merge(1, 2, dim == 2)]
        case%domain%dx = 0.5_wp
        case%domain%origin = [1.0_wp, -1.0_wp, merge(0.0_wp, 7.0_wp, dim == 2)]
        allocate (case%materials(2))
        case%materials(1)%name = "sand"
        case%materials(2)%name = "clay"
    end subroutine small_case

    !> n particles with nstate state variables and the affine velocities, a distinct value
    !> in every element of every field the table holds (positions inside the domain, material
    !> indices 1 or 2, ids 1..n).
    subroutine filled_particles(case, n, nstate, particles)
        type(case_type), intent(in) :: case
        integer, intent(in) :: n, nstate
        type(particles_type), intent(out) :: particles

        type(error_type), allocatable :: error
        type(particle_field_type) :: field
        real(wp), allocatable :: values(:, :)
        integer, allocatable :: integers(:)
        integer :: k, p, d

        call new_particles(particles, case%dim, n, error, nstate)
        call check(suite, .not. allocated(error), "new_particles")
        if (allocated(error)) return
        call hold_field(particles, field_index("affine"), error)
        call check(suite, .not. allocated(error), "hold_field affine")
        call hold_field(particles, field_index("body_force"), error)
        call check(suite, .not. allocated(error), "hold_field body_force")
        call hold_field(particles, field_index("load"), error)
        call check(suite, .not. allocated(error), "hold_field load")
        call hold_field(particles, field_index("load_share"), error)
        call check(suite, .not. allocated(error), "hold_field load_share")
        call hold_field(particles, field_index("pore_p"), error)
        call check(suite, .not. allocated(error), "hold_field pore_p")
        do k = 1, particle_field_count()
            if (.not. field_held(particles, k)) cycle
            field = particle_field(k)
            if (field%whole) then
                call get_field_integers(particles, k, integers)
                integers = [(1 + mod(p, 2), p = 1, n)]
                call put_field_integers(particles, k, integers)
            else
                call get_field(particles, k, values)
                do p = 1, size(values, 2)
                    do d = 1, size(values, 1)
                        values(d, p) = 1000.0_wp*k + 10.0_wp*p + d + 1.0_wp/7.0_wp
                    end do
                end do
                call put_field(particles, k, values)
            end if
        end do
        do p = 1, n
            do d = 1, case%dim
                particles%x(d, p) = case%domain%origin(d) + case%domain%ncells(d)*case%domain%dx* &
                    modulo(0.1_wp + 0.13_wp*p + 0.37_wp*d, 1.0_wp)
            end do
        end do
    end subroutine filled_particles

    !> The table itself: names unique and set, the state file's fields saved, the migration
    !> fields not.
    subroutine test_table()
        type(particle_field_type) :: a, b
        integer :: k, j
        logical :: unique

        call check(suite, particle_field_count() >= 15, "the table lists the 15 arrays")
        unique = .true.
        do k = 1, particle_field_count()
            a = particle_field(k)
            unique = unique .and. len_trim(a%name) > 0 .and. field_index(trim(a%name)) == k
            do j = k + 1, particle_field_count()
                b = particle_field(j)
                unique = unique .and. a%name /= b%name
            end do
        end do
        call check(suite, unique, "every field has its own name, found by field_index")
        a = particle_field(particle_field_count() + 1)
        call check(suite, len_trim(a%name) == 0, "no field after the last")
        call check(suite, field_index("none") == 0, "field_index of an unknown name is 0")
        a = particle_field(field_index("id"))
        call check(suite, field_index("id") == particle_field_count() .and. .not. a%saved, &
            "id is last (records are sorted by it) and not saved")
        a = particle_field(field_index("f"))
        call check(suite, values_per_particle(a, 3, 0) == 9 .and. &
            values_per_particle(a, 2, 0) == 4, "f has dim x dim values")
        a = particle_field(field_index("state"))
        call check(suite, values_per_particle(a, 3, 5) == 5, "state has nstate values")
        ! memory_estimate's count before the table: x, u, v, lp0; mass, volume, volume0;
        ! stress, strain; F; the state variables (reals) and the material (an integer)
        call check(suite, created_particle_bytes(2, 2, .false., .false.) == &
            8*(4*2 + 3 + 2*4 + 2*2 + 2) + 4, "bytes per particle created in 2D")
        call check(suite, created_particle_bytes(3, 2, .false., .false.) == &
            8*(4*3 + 3 + 2*6 + 3*3 + 2) + 4, "bytes per particle created in 3D")
        call check(suite, created_particle_bytes(3, 2, .true., .true.) == &
            8*(4*3 + 3 + 2*6 + 2*3*3 + 2) + 2*4, "with the affine velocities and the ids")
    end subroutine test_table

    !> Every saved field comes back bit for bit; the unsaved ones do not come back.
    subroutine test_round_trip(dim)
        integer, intent(in) :: dim

        type(case_type) :: case
        type(particles_type) :: saved, loaded
        type(particle_field_type) :: field
        type(error_type), allocatable :: error
        real(wp), allocatable :: a(:, :), b(:, :)
        integer, allocatable :: ia(:), ib(:)
        character(len=:), allocatable :: path, name
        real(wp) :: time
        integer :: step, k

        call small_case(case, dim)
        call filled_particles(case, 7, 2, saved)
        path = root//"/round_trip_"//achar(iachar("0") + dim)//"d.h5"
        call save_state(path, case, saved, 1.25_wp, 17, error)
        call check(suite, .not. allocated(error), "save_state")
        if (allocated(error)) return
        call note(path)
        call check(suite, state_particle_count(path) == 7, "state_particle_count")
        call load_state(path, case, loaded, time, step, error, 2)
        call check(suite, .not. allocated(error), "load_state")
        if (allocated(error)) then
            write (*, "(a)") error%message
            return
        end if
        call check(suite, time == 1.25_wp .and. step == 17, "time and step")
        call check(suite, loaded%n == 7 .and. loaded%dim == dim .and. loaded%nstate == 2, &
            "n, dim and nstate")
        do k = 1, particle_field_count()
            field = particle_field(k)
            name = trim(field%name)
            if (.not. field%saved) then
                call check(suite, .not. field_held(loaded, k), name//" is not saved")
                cycle
            end if
            call check(suite, field_held(loaded, k), name//" is read")
            if (.not. field_held(loaded, k)) cycle
            if (field%whole) then
                call get_field_integers(saved, k, ia)
                call get_field_integers(loaded, k, ib)
                call check(suite, size(ia) == size(ib), name//": size")
                if (size(ia) == size(ib)) call check(suite, all(ia == ib), name//": values")
            else
                call get_field(saved, k, a)
                call get_field(loaded, k, b)
                call check(suite, all(shape(a) == shape(b)), name//": shape")
                if (all(shape(a) == shape(b))) then
                    call check(suite, all(a == b), name//": values bit for bit")
                end if
            end if
        end do
    end subroutine test_round_trip

    !> A run that keeps no displacement, strain or affine velocities: zeros and no affine.
    subroutine test_dropped_fields()
        type(case_type) :: case
        type(particles_type) :: saved, loaded
        type(error_type), allocatable :: error
        character(len=:), allocatable :: path
        real(wp) :: time
        integer :: step

        call small_case(case, 2)
        call filled_particles(case, 4, 0, saved)
        deallocate (saved%u, saved%strain, saved%affine)
        path = root//"/dropped.h5"
        call save_state(path, case, saved, 0.5_wp, 3, error)
        call check(suite, .not. allocated(error), "save_state without u, strain, affine")
        if (allocated(error)) return
        call note(path)
        call load_state(path, case, loaded, time, step, error)
        call check(suite, .not. allocated(error), "load_state without u, strain, affine")
        if (allocated(error)) return
        call check(suite, allocated(loaded%u) .and. allocated(loaded%strain), &
            "u and strain held after loading")
        if (allocated(loaded%u)) call check(suite, all(loaded%u == 0.0_wp), "u zero")
        if (allocated(loaded%strain)) call check(suite, all(loaded%strain == 0.0_wp), &
            "strain zero")
        call check(suite, .not. allocated(loaded%affine), "no affine velocities")
        call check(suite, all(loaded%stress == saved%stress), "stress read")
        call check(suite, loaded%nstate == 0 .and. size(loaded%state, 1) == 0, &
            "no material state")
    end subroutine test_dropped_fields

    !> A file with 1 state variable loaded for a case of 3: the first, then zeros.
    subroutine test_more_state_variables()
        type(case_type) :: case
        type(particles_type) :: saved, loaded
        type(error_type), allocatable :: error
        character(len=:), allocatable :: path
        real(wp) :: time
        integer :: step

        call small_case(case, 2)
        call filled_particles(case, 5, 1, saved)
        path = root//"/state_1.h5"
        call save_state(path, case, saved, 0.0_wp, 0, error)
        call check(suite, .not. allocated(error), "save_state with 1 state variable")
        if (allocated(error)) return
        call note(path)
        call load_state(path, case, loaded, time, step, error, 3)
        call check(suite, .not. allocated(error), "load_state for 3 state variables")
        if (allocated(error)) return
        call check(suite, loaded%nstate == 3 .and. all(shape(loaded%state) == [3, 5]), &
            "3 state variables")
        if (loaded%nstate /= 3) return
        call check(suite, all(loaded%state(1, :) == saved%state(1, :)), "the file's first")
        call check(suite, all(loaded%state(2:3, :) == 0.0_wp), "then zeros")
    end subroutine test_more_state_variables

    !> A material whose type changed between the saving and the loading case starts its
    !> state afresh (zeros); one of the same type keeps it.
    subroutine test_type_change()
        type(case_type) :: case, other
        type(particles_type) :: saved, loaded
        type(error_type), allocatable :: error
        character(len=:), allocatable :: path
        real(wp) :: time
        integer :: step, p

        call small_case(case, 2)
        case%materials(1)%type = "mohr_coulomb"
        case%materials(2)%type = "mohr_coulomb"
        call filled_particles(case, 6, 2, saved)
        path = root//"/state_types.h5"
        call save_state(path, case, saved, 0.0_wp, 0, error)
        call check(suite, .not. allocated(error), "save_state with material types")
        if (allocated(error)) return
        call note(path)
        other = case
        other%materials(2)%type = "cam_clay"
        call load_state(path, other, loaded, time, step, error, 2)
        call check(suite, .not. allocated(error), "load_state, clay now cam_clay")
        if (allocated(error)) return
        call check(suite, any(loaded%material(1:loaded%n) == 1) .and. &
            any(loaded%material(1:loaded%n) == 2), "particles of both materials")
        do p = 1, loaded%n
            if (loaded%material(p) == 2) then
                call check(suite, all(loaded%state(:, p) == 0.0_wp), "another type: state zero")
            else
                call check(suite, all(loaded%state(:, p) == saved%state(:, p)), &
                    "same type: state kept")
            end if
        end do
    end subroutine test_type_change

    subroutine test_refusals()
        type(case_type) :: case, other
        type(particles_type) :: saved
        type(error_type), allocatable :: error
        character(len=:), allocatable :: path
        integer(hid_t) :: file
        integer :: hdferr

        call small_case(case, 2)
        call filled_particles(case, 3, 2, saved)
        path = root//"/refuse.h5"
        call save_state(path, case, saved, 2.0_wp, 7, error)
        call check(suite, .not. allocated(error), "save_state for refusals")
        if (allocated(error)) return
        call note(path)

        other = case
        other%domain%dx = 0.25_wp
        call expect_refusal(path, other, ["dx = 0.5 m ", "dx = 0.25 m"], "another dx")
        call small_case(other, 3)
        call expect_refusal(path, other, ["state has dimension 2", "case has dimension 3 "], &
            "another dimension")
        other = case
        other%materials(1)%name = "rock"
        call expect_refusal(path, other, ["material 'sand'"], "a material the case lacks")

        ! a file without a field the table requires
        call h5fopen_f(path, h5f_acc_rdwr_f, file, hdferr)
        call check(suite, hdferr == 0, "reopen the state")
        if (hdferr /= 0) return
        call h5ldelete_f(file, "/particles/volume0", hdferr)
        call check(suite, hdferr == 0, "delete /particles/volume0")
        call h5fclose_f(file, hdferr)
        call expect_refusal(path, case, ["no dataset '/particles/volume0'"], &
            "a state without volume0")
    end subroutine test_refusals

    !> load_state must fail with exit_input and a message naming the file and each part.
    subroutine expect_refusal(path, case, parts, what)
        character(len=*), intent(in) :: path
        type(case_type), intent(in) :: case
        character(len=*), intent(in) :: parts(:)
        character(len=*), intent(in) :: what

        type(particles_type) :: loaded
        type(error_type), allocatable :: error
        real(wp) :: time
        integer :: step, i

        call load_state(path, case, loaded, time, step, error, 2)
        call check(suite, allocated(error), "load_state refuses "//what)
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, "exit_input: "//what)
        call check_contains(suite, error%message, "'"//path//"'", &
            "the message names the file: "//what)
        do i = 1, size(parts)
            call check_contains(suite, error%message, trim(parts(i)), what)
        end do
    end subroutine expect_refusal

    !> Remember a file to delete at the end.
    subroutine note(path)
        character(len=*), intent(in) :: path

        call check(suite, file_exists(path), path//" written")
        nwritten = nwritten + 1
        written(nwritten) = path
    end subroutine note

end program test_mpm_state
