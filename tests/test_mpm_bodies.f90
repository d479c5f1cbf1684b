!> Bodies to particles: counts, positions, masses, volumes and GIMP sizes, for the regular and
!> the random distribution, in 2D and 3D.
program test_mpm_bodies
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_particles, only: particles_type
    use mpm_bodies, only: create_particles, count_body_particles
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: round_off = 100.0_wp*epsilon(1.0_wp)

    call new_suite(suite, "mpm_bodies")
    call check_case(2, "regular")
    call check_case(2, "random")
    call check_case(3, "regular")
    call check_case(3, "random")
    call finish(suite)

contains

    subroutine check_case(dim, distribution)
        integer, intent(in) :: dim
        character(len=*), intent(in) :: distribution

        type(case_type) :: case
        type(particles_type) :: particles, again
        type(error_type), allocatable :: error
        character(len=:), allocatable :: text, label
        real(wp) :: box_volume, h, sub(3)
        integer :: p, a, b, first, last, expected
        logical :: inside, in_subcell

        label = achar(48 + dim)//"D "//distribution
        if (dim == 2) then
            text = '{"domain": {"nx": 10, "ny": 8, "dx": 0.1, "origin": [-0.5, 0.2]}, '// &
                '"bodies": [{"material": "a", "min": [-0.5, 0.2], "max": [0.1, 0.5]}, '// &
                '{"material": "b", "min": [0.2, 0.2], "max": [0.45, 0.61]}], '
        else
            text = '{"domain": {"nx": 6, "ny": 5, "nz": 4, "dx": 0.1}, '// &
                '"bodies": [{"material": "a", "min": [0, 0, 0], "max": [0.3, 0.2, 0.4]}, '// &
                '{"material": "b", "min": [0.35, 0.3, 0.1], "max": [0.6, 0.5, 0.3]}], '
        end if
        text = text//'"particles": {"ppc": 3, "distribution": "'//distribution//'"}, '// &
            '"materials": [{"name": "a", "type": "linear_elastic", "E": 1e6, "nu": 0.3, '// &
            '"rho": 1000}, {"name": "b", "type": "linear_elastic", "E": 1e6, "nu": 0.3, '// &
            '"rho": 3000}], "time": {"tend": 1}}'
        call read_case_string(text, case, error)
        call check(suite, .not. allocated(error), label//": case valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call create_particles(case, particles, error)
        call check(suite, .not. allocated(error), label//": particles created")
        if (allocated(error)) return
        h = case%dx/case%ppc
        first = 1
        do b = 1, size(case%bodies)
            ! sub-cell centres inside [min, max): counted by hand per axis
            expected = 1
            do a = 1, dim
                expected = expected*count_centres(case%bodies(b)%xmin(a) - case%origin(a), &
                    case%bodies(b)%xmax(a) - case%origin(a), h)
            end do
            call check(suite, count_body_particles(case, b) == expected, &
                label//": particle count of a body")
            last = first + expected - 1
            box_volume = real(expected, wp)*h**dim
            call check_close(suite, sum(particles%volume(first:last)), box_volume, &
                round_off*box_volume, label//": volumes add up to the particles' cells")
            call check_close(suite, sum(particles%mass(first:last)), &
                case%materials(case%bodies(b)%material)%density*box_volume, &
                round_off*3000*box_volume, label//": mass = rho V")
            inside = .true.
            in_subcell = .true.
            do p = first, last
                do a = 1, dim
                    ! for the random distribution the point stays in its sub-cell, whose
                    ! centre is inside the body: the point is within h/2 of the box
                    inside = inside .and. particles%x(a, p) > case%bodies(b)%xmin(a) - h/2 &
                        .and. particles%x(a, p) < case%bodies(b)%xmax(a) + h/2
                    sub(a) = (particles%x(a, p) - case%origin(a))/h
                    in_subcell = in_subcell .and. sub(a) - floor(sub(a)) > 0.0_wp
                end do
                if (distribution == "regular") in_subcell = in_subcell .and. &
                    all(abs(sub(1:dim) - floor(sub(1:dim)) - 0.5_wp) < 1.0e-9_wp)
            end do
            call check(suite, inside, label//": particles inside their body")
            call check(suite, in_subcell, label//": particles at their sub-cell places")
            call check(suite, all(particles%material(first:last) == case%bodies(b)%material), &
                label//": material index")
            first = last + 1
        end do
        call check(suite, particles%n == first - 1, label//": no particle outside the bodies")
        call check(suite, all(abs(particles%lp - h/2) < round_off*h), label//": lp = h/2")
        call create_particles(case, again, error)
        call check(suite, all(again%x == particles%x), label//": placement is reproducible")
    end subroutine check_case

    !> Number of sub-cell centres (s + 1/2) h, s >= 0, inside [lo, hi).
    integer function count_centres(lo, hi, h)
        real(wp), intent(in) :: lo, hi, h
        integer :: s
        count_centres = 0
        do s = 0, 10000
            if ((s + 0.5_wp)*h >= lo .and. (s + 0.5_wp)*h < hi) count_centres = count_centres + 1
        end do
    end function count_centres

end program test_mpm_bodies
