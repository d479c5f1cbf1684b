!> Verification of the STL terrain contact (contact.type = "terrain_stl"): a block sliding on
!> an STL floor under a tilted gravity vector (../shared/REFERENCES.md section 4).
!>
!> The floor is the plane y = 0.11 m of tests/data/stl/floor_*.stl, between two grid lines
!> (dx = 0.02 m), so the contact is found from the distances to the surface, not from a face
!> of the grid. Gravity g (sin theta, -cos theta), theta = 30 deg, Coulomb friction mu. Exact:
!> s(t) = g (sin theta - mu cos theta) t^2 / 2 while mu < tan theta; the block sticks for
!> mu >= tan theta. Checked: the mean displacement along the floor within 2 % for mu = 0 and
!> 0.4, below 0.2 % of the frictionless slide for mu = 0.6, no lift-off, no particle below
!> the floor, and the same slide (to 1e-9) with the floor as 2 or as 2 000 triangles.
!>
!> Then the slope itself tilted by theta in the grid, gravity vertical, and the block a
!> rectangle turned with it (a body from a closed STL surface): the displacement along the
!> slope within 2 % of the same s(t) for mu = 0, 0.2, 0.4, the block sticks for mu = 0.6, and
!> the slope as 2 or 2 000 triangles gives the same slide. The STL files are written by the
!> test into a temporary folder.
program test_terrain_slide
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish, temporary_folder
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, advance, stable_time_step
    use mpm_setup, only: start_simulation
    use mpm_particle_domain, only: domain_half_sizes
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: g = 9.81_wp, tend = 0.5_wp, floor_y = 0.11_wp
    real(wp) :: theta, s_free, s2, s2000

    call new_suite(suite, "terrain_slide")
    theta = acos(-1.0_wp)/6
    s_free = 0.5_wp*g*sin(theta)*tend**2
    call run_block(0.0_wp, "0.0", "floor_2", s2)
    call run_block(0.6_wp, "0.6", "floor_2", s2)
    call run_block(0.4_wp, "0.4", "floor_2", s2)
    ! the triangulation does not matter
    call run_block(0.4_wp, "0.4", "floor_2000", s2000)
    call check_close(suite, s2000, s2, 1.0e-9_wp*abs(s2), &
        "the same slide on 2 and on 2 000 triangles")
    call tilted_slope()
    call finish(suite)

contains

    subroutine run_block(mu, mu_text, floor, s)
        real(wp), intent(in) :: mu
        character(len=*), intent(in) :: mu_text, floor
        real(wp), intent(out) :: s

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=64) :: gravity
        character(len=:), allocatable :: label
        real(wp) :: s_exact, lift, lowest, lp(2)
        integer :: p

        s = 0.0_wp
        label = "mu = "//mu_text//", "//floor
        write (gravity, "(a,es23.16,a,es23.16,a)") "[", g*sin(theta), ", ", -g*cos(theta), "]"
        call read_case_string('{"name": "block", "domain": {"nx": 60, "ny": 10, "dx": 0.02}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e8, "nu": 0.3, "rho": 2000}], "bodies": [{"material": "m", '// &
            '"min": [0.1, 0.11], "max": [0.3, 0.15]}], "gravity": '//trim(gravity)//', '// &
            '"contact": {"type": "terrain_stl", "mu": '//mu_text//', "file": '// &
            '"tests/data/stl/'//floor//'.stl"}, '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 0.5, "cfl": 0.5}}', case, error, "block")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call start_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": the floor is read")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        ! the nodes within two cells of the floor (rows y = 0.08 .. 0.14 of 61 nodes, the
        ! column on the x max face of the domain too) are the terrain pairs
        call check(suite, count(sim%grid%terrain_pair > 0) == 4*61, label// &
            ": the nodes within two cells of the floor, and only they, are terrain pairs")
        do while (sim%time < tend)
            call advance(sim, min(stable_time_step(sim), tend - sim%time), error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
        end do
        s = sum(sim%particles%mass*sim%particles%u(1, :))/sum(sim%particles%mass)
        lift = maxval(sim%particles%u(2, :))
        lowest = huge(1.0_wp)
        do p = 1, sim%particles%n
            call domain_half_sizes(sim%particles%f(:, :, p), sim%particles%lp0(:, p), 2, lp)
            lowest = min(lowest, sim%particles%x(2, p) - lp(2))
        end do
        if (mu < tan(theta)) then
            s_exact = 0.5_wp*g*(sin(theta) - mu*cos(theta))*tend**2
            call check_close(suite, s, s_exact, 0.02_wp*s_exact, &
                label//": slide s = g (sin - mu cos) t^2 / 2 within 2 %")
            print "(a,2(a,es11.4))", label, ": s = ", s, ", error ", s/s_exact - 1
        else
            call check(suite, abs(s) < 2.0e-3_wp*s_free, label// &
                ": the block sticks (|s| < 0.2 % of the frictionless slide)")
            print "(a,a,es11.4)", label, ": s = ", s
        end if
        call check(suite, lift < 1.0e-3_wp, label//": the block does not lift off")
        call check(suite, lowest > floor_y - 1.0e-3_wp, label// &
            ": no particle domain sinks more than 1 mm into the floor")
    end subroutine run_block

    !> The slope y = 0.75 - tan(theta) x tilted in the grid, gravity (0, -g).
    subroutine tilted_slope()
        character(len=:), allocatable :: dir
        real(wp) :: s, s_plane2, s_plane2000

        dir = temporary_folder("mpm_terrain_test")
        call write_slope(dir//"/slope_2.stl", 1)
        call write_slope(dir//"/slope_2000.stl", 1000)
        call write_block(dir//"/block.stl")
        call run_tilted(0.0_wp, "0.0", dir, "slope_2", s)
        call run_tilted(0.2_wp, "0.2", dir, "slope_2", s)
        call run_tilted(0.6_wp, "0.6", dir, "slope_2", s)
        call run_tilted(0.4_wp, "0.4", dir, "slope_2", s_plane2)
        call run_tilted(0.4_wp, "0.4", dir, "slope_2000", s_plane2000)
        call check_close(suite, s_plane2000, s_plane2, 1.0e-6_wp*abs(s_plane2), &
            "tilted slope: the same slide on 2 and on 2 000 triangles")
        call execute_command_line("rm -rf '"//dir//"'")
    end subroutine tilted_slope

    pure real(wp) function slope_y(x)
        real(wp), intent(in) :: x
        slope_y = 0.75_wp - tan(theta)*x
    end function slope_y

    !> The slope over x in [-0.2, 1.8] m, z in [-0.5, 0.5] m as m strips of 2 triangles.
    subroutine write_slope(path, m)
        character(len=*), intent(in) :: path
        integer, intent(in) :: m

        integer :: unit, i
        real(wp) :: xa, xb, a(3), b(3), c(3), d(3)

        open (newunit=unit, file=path, status="replace", action="write")
        write (unit, "(a)") "solid slope"
        do i = 0, m - 1
            xa = -0.2_wp + 2.0_wp*real(i, wp)/m
            xb = -0.2_wp + 2.0_wp*real(i + 1, wp)/m
            a = [xa, slope_y(xa), -0.5_wp]
            b = [xb, slope_y(xb), -0.5_wp]
            c = [xb, slope_y(xb), 0.5_wp]
            d = [xa, slope_y(xa), 0.5_wp]
            call put_triangle(unit, a, c, b)
            call put_triangle(unit, a, d, c)
        end do
        write (unit, "(a)") "endsolid slope"
        close (unit)
    end subroutine write_slope

    !> A 0.2 m x 0.04 m rectangle lying on the slope 2 mm above it (from x = 0.2 m), turned
    !> with it and extruded over z in [-0.1, 0.1] m: a closed surface, normals outwards.
    subroutine write_block(path)
        character(len=*), intent(in) :: path

        integer :: unit, i
        real(wp) :: p(2, 4), n(2), t(2), z0, z1

        n = [sin(theta), cos(theta)]
        t = [cos(theta), -sin(theta)]
        p(:, 1) = [0.2_wp, slope_y(0.2_wp)] + 0.002_wp*n
        p(:, 2) = p(:, 1) + 0.2_wp*t
        p(:, 3) = p(:, 2) + 0.04_wp*n
        p(:, 4) = p(:, 1) + 0.04_wp*n
        z0 = -0.1_wp
        z1 = 0.1_wp
        open (newunit=unit, file=path, status="replace", action="write")
        write (unit, "(a)") "solid block"
        ! p runs clockwise seen from +z (t points down the slope, n up): the z1 face takes the
        ! corners in reverse order to face +z
        call put_triangle(unit, [p(:, 1), z0], [p(:, 2), z0], [p(:, 3), z0])
        call put_triangle(unit, [p(:, 1), z0], [p(:, 3), z0], [p(:, 4), z0])
        call put_triangle(unit, [p(:, 1), z1], [p(:, 3), z1], [p(:, 2), z1])
        call put_triangle(unit, [p(:, 1), z1], [p(:, 4), z1], [p(:, 3), z1])
        do i = 1, 4
            associate (a => p(:, i), b => p(:, mod(i, 4) + 1))
                call put_triangle(unit, [a, z0], [b, z1], [b, z0])
                call put_triangle(unit, [a, z0], [a, z1], [b, z1])
            end associate
        end do
        write (unit, "(a)") "endsolid block"
        close (unit)
    end subroutine write_block

    subroutine put_triangle(unit, a, b, c)
        integer, intent(in) :: unit
        real(wp), intent(in) :: a(3), b(3), c(3)

        write (unit, "(a)") "  facet normal 0 0 0", "    outer loop"
        write (unit, "(a,3es25.16e3)") "      vertex ", a
        write (unit, "(a,3es25.16e3)") "      vertex ", b
        write (unit, "(a,3es25.16e3)") "      vertex ", c
        write (unit, "(a)") "    endloop", "  endfacet"
    end subroutine put_triangle

    subroutine run_tilted(mu, mu_text, dir, slope, s)
        real(wp), intent(in) :: mu
        character(len=*), intent(in) :: mu_text, dir, slope
        real(wp), intent(out) :: s

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=:), allocatable :: label
        real(wp) :: s_exact, t(2)

        s = 0.0_wp
        label = "tilted slope, mu = "//mu_text//", "//slope
        call read_case_string('{"name": "tilted", "domain": {"nx": 80, "ny": 40, "dx": 0.02}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e8, "nu": 0.3, "rho": 2000}], "bodies": [{"material": "m", "file": "'// &
            dir//'/block.stl"}], "gravity": [0, -9.81], '// &
            '"contact": {"type": "terrain_stl", "mu": '//mu_text//', "file": "'//dir//'/'// &
            slope//'.stl"}, "solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 0.5, "cfl": 0.5}}', case, error, "tilted")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call start_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": the slope is read")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        do while (sim%time < tend)
            call advance(sim, min(stable_time_step(sim), tend - sim%time), error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
        end do
        ! mean displacement along the slope, downwards
        t = [cos(theta), -sin(theta)]
        s = sum(sim%particles%mass*(t(1)*sim%particles%u(1, :) + t(2)*sim%particles%u(2, :))) &
            /sum(sim%particles%mass)
        if (mu < tan(theta)) then
            s_exact = 0.5_wp*g*(sin(theta) - mu*cos(theta))*tend**2
            call check_close(suite, s, s_exact, 0.02_wp*s_exact, &
                label//": slide s = g (sin - mu cos) t^2 / 2 within 2 %")
            print "(a,2(a,es11.4))", label, ": s = ", s, ", error ", s/s_exact - 1
        else
            call check(suite, abs(s) < 2.0e-3_wp*s_free, label// &
                ": the block sticks (|s| < 0.2 % of the frictionless slide)")
            print "(a,a,es11.4)", label, ": s = ", s
        end if
    end subroutine run_tilted

end program test_terrain_slide
