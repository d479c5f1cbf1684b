!> Fill the bodies of a case with particles.
module mpm_bodies
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type
    use mpm_case, only: case_type, body_subcell_range, dist_random
    use mpm_particles, only: particles_type, new_particles
    implicit none
    private
    public :: count_body_particles, create_particles

contains

    !> Number of particles a body holds (see body_subcell_range for the placement rule).
    pure integer(i8) function count_body_particles(case, b)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: b
            !! body index

        integer :: lo(3), hi(3), a

        call body_subcell_range(case, case%bodies(b), lo, hi)
        count_body_particles = 1_i8
        do a = 1, case%dim
            count_body_particles = count_body_particles*int(max(0, hi(a) - lo(a) + 1), i8)
        end do
    end function count_body_particles

    !> Create the particles of every body: positions, volumes, masses, velocities, sizes.
    subroutine create_particles(case, particles, error, nstate)
        type(case_type), intent(in) :: case
            !! resolved case
        type(particles_type), intent(out) :: particles
            !! the particles, body by body in case order
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)

        integer :: b, a, p, lo(3), hi(3), s(3), i, j, k, dim
        integer(i8) :: total
        real(wp) :: h, vol, jitter(3)

        dim = case%dim
        total = 0
        do b = 1, size(case%bodies)
            total = total + count_body_particles(case, b)
        end do
        call new_particles(particles, dim, int(total), error, nstate)
        if (allocated(error)) return

        h = case%dx/real(case%ppc, wp)
        vol = h**dim
        p = 0
        do b = 1, size(case%bodies)
            associate (body => case%bodies(b), rho => case%materials(case%bodies(b)%material)%density)
                call body_subcell_range(case, body, lo, hi)
                do k = lo(3), hi(3)
                    do j = lo(2), hi(2)
                        do i = lo(1), hi(1)
                            p = p + 1
                            s = [i, j, k]
                            jitter = 0.5_wp
                            if (case%distribution == dist_random) then
                                do a = 1, dim
                                    jitter(a) = uniform01(case%seed, p, a)
                                end do
                            end if
                            do a = 1, dim
                                particles%x(a, p) = case%origin(a) + (real(s(a), wp) + jitter(a))*h
                            end do
                            particles%v(:, p) = body%velocity(1:dim)
                            particles%volume(p) = vol
                            particles%volume0(p) = vol
                            particles%mass(p) = rho*vol
                            particles%lp0(:, p) = 0.5_wp*h
                            particles%lp(:, p) = 0.5_wp*h
                            particles%material(p) = body%material
                        end do
                    end do
                end do
            end associate
        end do
    end subroutine create_particles

    !> Reproducible uniform number in (0.05, 0.95) from (seed, particle, axis): splitmix64 hash.
    !>
    !> Independent of loop order and thread count; the margin keeps a particle off the
    !> faces of its sub-cell.
    pure real(wp) function uniform01(seed, p, axis)
        integer, intent(in) :: seed
            !! user seed
        integer, intent(in) :: p
            !! particle index
        integer, intent(in) :: axis
            !! coordinate axis

        integer(i8) :: z

        z = int(seed, i8)*1000003_i8 + int(p, i8)*3_i8 + int(axis, i8)
        z = z + (-7046029254386353131_i8)
        z = ieor(z, shiftr(z, 30))*(-4658895280553007687_i8)
        z = ieor(z, shiftr(z, 27))*(-7723592293110705685_i8)
        z = ieor(z, shiftr(z, 31))
        uniform01 = 0.05_wp + 0.9_wp*real(shiftr(z, 11), wp)/real(shiftl(1_i8, 53), wp)
    end function uniform01

end module mpm_bodies
