!> Bodies to particles: counts, positions, masses, volumes and GIMP sizes, for the regular and
!> the random distribution, in 2D and 3D; bodies from closed STL surfaces (tests/data/stl).
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
    call check_stl_cube("regular")
    call check_stl_cube("random")
    call check_tilted_box()
    call check_prism()
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
        h = case%domain%dx/case%particles%ppc
        first = 1
        do b = 1, size(case%bodies)
            ! sub-cell centres inside [min, max): counted by hand per axis
            expected = 1
            do a = 1, dim
                expected = expected*count_centres(case%bodies(b)%xmin(a) - case%domain%origin(a), &
                    case%bodies(b)%xmax(a) - case%domain%origin(a), h)
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
                    sub(a) = (particles%x(a, p) - case%domain%origin(a))/h
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
        call check(suite, all(abs(particles%lp0 - h/2) < round_off*h), label//": lp0 = h/2")
        call create_particles(case, again, error)
        call check(suite, all(again%x == particles%x), label//": placement is reproducible")
    end subroutine check_case

    !> The unit cube STL scaled and moved onto a box gives that box's particles, after a box
    !> body (so the random jitter's numbering of the sites is checked too).
    subroutine check_stl_cube(distribution)
        character(len=*), intent(in) :: distribution
            !! "regular" or "random"

        type(case_type) :: box_case, stl_case
        type(particles_type) :: box, stl
        type(error_type), allocatable :: error
        character(len=:), allocatable :: head, tail, label

        label = "STL cube "//distribution
        head = '{"domain": {"nx": 6, "ny": 7, "nz": 5, "dx": 0.1}, "bodies": [' &
            //'{"material": "a", "min": [0.45, 0, 0], "max": [0.6, 0.2, 0.2]}, '
        tail = '], "particles": {"ppc": 3, "distribution": "'//distribution//'"}, ' &
            //'"materials": [{"name": "a", "type": "linear_elastic", "E": 1e6, "nu": 0.3, ' &
            //'"rho": 1000}], "time": {"tend": 1}}'
        call read_case_string(head//'{"material": "a", "min": [0.1, 0.2, 0.1], ' &
            //'"max": [0.4, 0.5, 0.4]}'//tail, box_case, error)
        call check(suite, .not. allocated(error), label//": box case valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call read_case_string(head//'{"material": "a", "file": "tests/data/stl/unit_cube.stl", ' &
            //'"scale": 0.3, "offset": [0.1, 0.2, 0.1]}'//tail, stl_case, error)
        call check(suite, .not. allocated(error), label//": STL case valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call check(suite, count_body_particles(stl_case, 2) == count_body_particles(box_case, 2) &
            .and. count_body_particles(box_case, 2) == 9**3, label//": count of the equal box")
        call create_particles(box_case, box, error)
        if (allocated(error)) return
        call create_particles(stl_case, stl, error)
        call check(suite, .not. allocated(error), label//": particles created")
        if (allocated(error)) return
        call check(suite, stl%n == box%n, label//": as many particles as the box")
        if (stl%n /= box%n) return
        ! the same lattice and jitter: the same numbers, not just close ones
        call check(suite, all(stl%x == box%x), label//": positions of the equal box")
    end subroutine check_stl_cube

    !> A cube turned 30 degrees about z: its volume to the lattice's resolution, every particle
    !> inside it.
    subroutine check_tilted_box()
        type(case_type) :: case
        type(particles_type) :: particles
        type(error_type), allocatable :: error
        real(wp), parameter :: side = 0.4_wp, centre(3) = [0.5_wp, 0.5_wp, 0.3_wp]
        ! the fixture's corners are real32: within 1e-7 relative of the exact cube
        real(wp), parameter :: slack = 1.0e-6_wp
        real(wp) :: h, c, s, local(3)
        integer :: p
        logical :: inside

        call read_case_string('{"domain": {"nx": 10, "ny": 10, "nz": 6, "dx": 0.1}, ' &
            //'"bodies": [{"material": "a", "file": "tests/data/stl/tilted_box.stl"}], ' &
            //'"particles": {"ppc": 4}, "materials": [{"name": "a", "type": ' &
            //'"linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}], "time": {"tend": 1}}', &
            case, error)
        call check(suite, .not. allocated(error), "tilted box: case valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call create_particles(case, particles, error)
        call check(suite, .not. allocated(error), "tilted box: particles created")
        if (allocated(error)) return
        h = case%domain%dx/case%particles%ppc
        call check(suite, particles%n == count_body_particles(case, 1), &
            "tilted box: count = particles created")
        ! the sub-cells cut by the 4 tilted faces err either way: about (sides x h) / 2
        ! at most, here 0.4 x 0.4 x 4 x 0.025 / 2 = 8e-3 m3 bound, far less on average; 2 %
        ! is the issue's requirement
        call check_close(suite, real(particles%n, wp)*h**3, side**3, 0.02_wp*side**3, &
            "tilted box: volume within 2 %")
        c = cos(acos(-1.0_wp)/6)
        s = sin(acos(-1.0_wp)/6)
        inside = .true.
        do p = 1, particles%n
            local = particles%x(:, p) - centre
            local(1:2) = [c*local(1) + s*local(2), -s*local(1) + c*local(2)]
            inside = inside .and. all(abs(local) <= side/2 + slack)
        end do
        call check(suite, inside, "tilted box: every particle inside the turned cube")
    end subroutine check_tilted_box

    !> 2D: a prism across z = 0 fills its triangular section, exactly the sub-cell centres
    !> inside the triangle.
    subroutine check_prism()
        type(case_type) :: case
        type(particles_type) :: particles
        type(error_type), allocatable :: error
        real(wp) :: h, x, y
        integer :: i, j, expected
        logical :: inside

        call read_case_string('{"dimension": 2, "domain": {"nx": 10, "ny": 8, "dx": 0.1}, ' &
            //'"bodies": [{"material": "a", "file": "tests/data/stl/prism.stl"}], ' &
            //'"particles": {"ppc": 4}, "materials": [{"name": "a", "type": ' &
            //'"linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}], "time": {"tend": 1}}', &
            case, error)
        call check(suite, .not. allocated(error), "prism: 2D case valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call create_particles(case, particles, error)
        call check(suite, .not. allocated(error), "prism: particles created")
        if (allocated(error)) return
        h = case%domain%dx/case%particles%ppc
        ! sub-cell centres inside the triangle (0.1, 0.1), (0.7, 0.1), (0.1, 0.5), by hand
        expected = 0
        do j = 0, 31
            do i = 0, 39
                x = (i + 0.5_wp)*h
                y = (j + 0.5_wp)*h
                if (in_triangle(x, y)) expected = expected + 1
            end do
        end do
        call check(suite, particles%n == expected .and. expected > 0, &
            "prism: the sub-cell centres inside the triangle")
        inside = .true.
        do i = 1, particles%n
            inside = inside .and. in_triangle(particles%x(1, i), particles%x(2, i))
        end do
        call check(suite, inside, "prism: every particle inside the triangle")
        ! area 0.12 m2; the cut sub-cells along the slanted side err either way
        call check_close(suite, real(particles%n, wp)*h**2, 0.12_wp, 0.05_wp*0.12_wp, &
            "prism: area within 5 %")
    end subroutine check_prism

    !> Whether (x, y) is inside the prism's triangle (0.1, 0.1), (0.7, 0.1), (0.1, 0.5).
    pure logical function in_triangle(x, y)
        real(wp), intent(in) :: x
            !! abscissa [m]
        real(wp), intent(in) :: y
            !! ordinate [m]
        in_triangle = x > 0.1_wp .and. y > 0.1_wp &
            .and. (x - 0.1_wp)/0.6_wp + (y - 0.1_wp)/0.4_wp < 1.0_wp
    end function in_triangle

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
